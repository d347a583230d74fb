#pragma once
// Polygons in face-to-face contact: in one plane, facing each other, their bounds overlapping (a
// box standing on the floor, a handle on a drawer, a sideboard's back against a wall). Where they
// overlap each sees only the other; the ray caster, which ignores polygons through a ray's ends,
// cannot tell, so the radiosity solvers ask this.

#include <vector>

#include "penumbra/scene/posed_scene.h"

namespace penumbra {

// For each polygon, the polygons in face-to-face contact with it (within 1e-9 of the scene's
// size of one plane).
std::vector<std::vector<PolygonId>> faceContacts(const PosedScene& scene);

}  // namespace penumbra
