#pragma once
// Enumerates the EV discontinuity surfaces of one light (Drettakis & Fiume 1994 §3): light vertex ×
// occluder edge, and light edge × occluder vertex, keeping only occluder features that can be
// silhouettes from the light feature (exact predicates, conservative) and lie in front of the
// light. Non-emitter EV and EEE surfaces are not enumerated yet.

#include <vector>

#include "penumbra/dm/discontinuity_surface.h"
#include "penumbra/dm/edge_adjacency.h"

namespace penumbra {

std::vector<DiscontinuitySurface> enumerateEmitterEvSurfaces(const PosedScene& scene,
                                                             const EdgeAdjacency& adjacency,
                                                             PolygonId light, SurfaceId firstId);

}  // namespace penumbra
