#pragma once
// Real scene files repeat vertices: a polygon closed by repeating its first vertex at the end, a
// consecutive duplicate, an OBJ face `f a b b c d`. A repeated corner carries no geometry, but
// every engine assumes that consecutive corners differ (an edge of zero length has no direction:
// EEE tracing and horizon events crashed on them). The loaders remove them before validation.

#include "penumbra/scene/scene.h"

namespace penumbra {

// Removes from every polygon each corner exactly equal to the one before it (cyclically, so a
// closing repeat of the first corner goes too). Returns how many corners were removed. A polygon
// left with fewer than 3 corners is left for validation to reject.
long long removeRepeatedVertices(Scene& scene);

}  // namespace penumbra
