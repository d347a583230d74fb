#pragma once
// Bounds that do not depend on the frame: where an object can be over a step of its motion, and
// where anything of the scene can be over all of its keyframes. Frame-invariant tolerances and the
// shared grid are taken from the scene's reach, so that a solution updated to frame K and one
// computed from scratch at frame K use the same numbers.

#include <vector>

#include "penumbra/geometry/box.h"
#include "penumbra/geometry/polygon.h"
#include "penumbra/geometry/transform.h"

namespace penumbra {

struct Scene;
struct SceneObject;

// World bounds of object-space polygons under `transform`.
Box3 transformedBounds(const std::vector<Polygon3>& polygons, const Transform& transform);

// Contains every pose of the polygons between transforms a and b under keyframe interpolation
// (translation and scale linear, rotation by slerp). Exact (the union of both ends' bounds) when
// the linear parts are equal, since every point then moves on a segment; otherwise conservative:
// each point x = T(t) + R(t) S(t) p stays within |S(t) p| of the segment T_a T_b (a rotation keeps
// lengths), and |S(t) p| <= max(||L_a||_F, ||L_b||_F) |p| (scale interpolates per axis).
Box3 sweptBounds(const std::vector<Polygon3>& polygons, const Transform& a, const Transform& b);

// Every pose the object takes over its whole motion (its static transform's bounds if it has none).
Box3 reachBounds(const SceneObject& object);

// The union of reachBounds over the scene's objects.
Box3 reachBounds(const Scene& scene);

}  // namespace penumbra
