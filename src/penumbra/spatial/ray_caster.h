#pragma once
// Ray and segment queries against the polygons of a posed scene, accelerated by Embree 3.
//
// Structure. Two levels, as Embree recommends for scenes with moving parts: each object's
// triangles are one Embree scene of their own (in world coordinates), instanced with the identity
// transform into a top-level scene. Moving an object rebuilds only that object's BVH and the
// top-level one over the instances (moveObject), so the cost of a move follows the object, not the
// scene. A caster moved to a pose and one built at that pose hold the same triangles in the same
// per-object structures, hence give the same hits.
//
// Precision. Embree stores triangles and traverses rays in single precision. To keep that error
// relative to the scene rather than to the distance from the world origin, coordinates are given
// to Embree relative to the centre of the scene's bounding box; the absolute error of a position
// is then about 1e-7 x the scene's half-diagonal. Consequences:
//  - near polygon edges a ray may pass on either side of the exact answer within that error;
//  - a ray leaving a surface can hit that same surface again near t = 0 (self-intersection). The
//    scene-relative tolerance epsilon() = kRelativeEpsilon x scene diagonal (about 100 float
//    ulps of the largest recentred coordinate) is what callers should use to step off surfaces;
//  - query points should lie in or near the scene's bounds; far outside, their own float rounding
//    grows with their distance from the centre.
// The centre and epsilon() come from PosedScene::extent (every pose the scene can reach), so they
// do not change when objects move.
// Returned hit parameters and points are recomputed in double precision on the hit polygon's plane,
// so they are accurate even though the hit was found in float.

#include <memory>
#include <optional>
#include <vector>

#include "penumbra/geometry/vec3.h"
#include "penumbra/scene/posed_scene.h"

namespace penumbra {

struct RayHit {
  PolygonId polygon = -1;
  double t = 0;  // hit = origin + t * direction (t in units of the direction given)
  Vec3 point;
};

class RayCaster {
 public:
  // Relative tolerance: epsilon() = kRelativeEpsilon x the diagonal of the scene's bounding box.
  static constexpr double kRelativeEpsilon = 1e-5;
  static constexpr PolygonId kNoPolygon = -1;

  // Builds the acceleration structure for every polygon of `scene` (each triangulated; polygons
  // with zero area cannot be hit). The scene is not referenced afterwards. Throws
  // std::runtime_error if Embree cannot create its device or lacks a feature we need (two-sided
  // triangles, filters).
  explicit RayCaster(const PosedScene& scene);
  ~RayCaster();
  // A moved-from caster may only be destroyed or assigned to.
  RayCaster(RayCaster&&) noexcept;
  RayCaster& operator=(RayCaster&&) noexcept;
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  // The closest polygon met by origin + t * direction for t in [tMin, tMax], or nothing. Polygons
  // are hit from both sides. `ignored` (if not kNoPolygon) is never hit: use it for the polygon a
  // ray leaves. Preconditions: direction is non-zero, 0 <= tMin <= tMax (tMax may be infinite).
  // Postcondition: tMin <= hit.t <= tMax. Thread-safe.
  std::optional<RayHit> intersect(const Vec3& origin, const Vec3& direction, double tMin,
                                  double tMax, PolygonId ignored = kNoPolygon) const;

  // Does any polygon block the open segment between `from` and `to`? Endpoints are excluded: a
  // polygon whose supporting plane passes within epsilon() of `from` or of `to` does not occlude
  // (the segment can cross that plane only at the endpoint, so a hit there is the endpoint
  // itself). So a segment from a receiver point to a sample on a light is not blocked by the
  // receiver or by the light, whatever the angle, while every other polygon, lights included,
  // blocks it. Equal endpoints are never occluded. Thread-safe.
  bool isOccluded(const Vec3& from, const Vec3& to) const;

  // Re-reads the polygons of `objects` from `scene` (their new pose; the scene's extent unchanged)
  // and recommits. Not thread-safe: no query may run meanwhile.
  void moveObjects(const PosedScene& scene, const std::vector<int>& objects);

  // Absolute distance tolerance of this scene (see the file comment).
  double epsilon() const;
  // Triangles given to Embree (for statistics).
  int triangleCount() const;

  struct Impl;  // Embree state, defined in ray_caster.cpp

 private:
  std::unique_ptr<Impl> impl_;
};

// The surface a ray sees first: intersect's hit, except where two polygons back to back in one
// plane (the two sides of a two-sided card) meet the ray at one distance, within epsilon(): the
// caster returns either, and the side facing the ray is the one seen.
std::optional<RayHit> firstSurfaceSeen(const RayCaster& rays, const PosedScene& scene,
                                       const Vec3& origin, const Vec3& direction, double tMin,
                                       double tMax, PolygonId ignored = RayCaster::kNoPolygon);

}  // namespace penumbra
