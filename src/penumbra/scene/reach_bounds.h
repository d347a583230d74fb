#pragma once
// Bounds that do not depend on the frame: where an object can be over a step of its motion, and
// where anything of the scene can be over all of its keyframes. Frame-invariant tolerances and the
// shared grid are taken from the scene's reach, so that a solution updated to frame K and one
// computed from scratch at frame K use the same numbers.

#include <vector>

#include "penumbra/geometry/box.h"
#include "penumbra/geometry/polygon.h"
#include "penumbra/geometry/transform.h"
#include "penumbra/scene/motion.h"

namespace penumbra {

struct Scene;
struct SceneObject;

// World bounds of object-space polygons under `transform`.
Box3 transformedBounds(const std::vector<Polygon3>& polygons, const Transform& transform);

// Contains every pose of the polygons between keyframe poses a and b under keyframe interpolation
// (translation and scale linear, rotation by slerp). Exact (the union of both ends' bounds) when
// the rotations are equal, since every point then moves on a segment. Otherwise conservative: the
// step is cut into 64 parts; over a part, the object's bounding-box centre c moves by at most
// |ΔT| + |ΔS c| + φ |S c| (φ the part's rotation angle: a rotation by φ moves a vector by at most
// φ times its length), and every point stays within max|s| |p − c| of the centre.
Box3 sweptBounds(const std::vector<Polygon3>& polygons, const TrsPose& a, const TrsPose& b);

// Every pose the object takes between two frames of its keyframed motion (its static pose's bounds
// if it has none).
Box3 sweptBounds(const SceneObject& object, double fromFrame, double toFrame);

// Every pose the object takes over its whole motion (its static transform's bounds if it has none).
Box3 reachBounds(const SceneObject& object);

// The union of reachBounds over the scene's objects.
Box3 reachBounds(const Scene& scene);

}  // namespace penumbra
