#pragma once
// Polygons in face-to-face contact: in one plane, facing each other, their bounds overlapping (a
// box standing on the floor, a handle on a drawer, a sideboard's back against a wall). Where they
// overlap each sees only the other; the ray caster, which ignores polygons through a ray's ends,
// cannot tell, so the radiosity solvers ask this.

#include <vector>

#include "penumbra/scene/posed_scene.h"

namespace penumbra {

// For each polygon, the polygons in face-to-face contact with it (within 1e-9 of the scene's
// size of one plane). Also the two sides of a sheet (a two-sided card: open space on both
// sides), which the hierarchical solver, the one user, takes as covering each other.
std::vector<std::vector<PolygonId>> faceContacts(const PosedScene& scene);

// For each polygon, the polygons that may cover part of it: those in face-to-face contact with it
// (not the other side of a sheet, told apart by rays from between them against the two polygons'
// objects: taken as covering each other, both sides of a two-sided card received nothing), and
// those lying on it in one plane facing the same way that come later in the scene (a rug on a
// floor, a decal, a box's bottom on the floor with its faces turned inwards: the later lies on
// top), except that a light lies on top of a polygon that emits nothing (a lamp set into the
// ceiling's plane, whichever comes first). Where a polygon is covered it neither receives nor sends
// light. Without the second kind both polygons of such a pair take the light that arrives where
// they overlap and both send it on: a closed cavity over such a pair (an inside-out box standing on
// the floor) returns more light than reaches it, and its radiosity grew without bound (1e5 times
// the room's, refinement past millions of links).
std::vector<std::vector<PolygonId>> coveringPolygons(const PosedScene& scene);

}  // namespace penumbra
