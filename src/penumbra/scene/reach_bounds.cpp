#include "penumbra/scene/reach_bounds.h"

#include <algorithm>
#include <cmath>

#include "penumbra/scene/scene.h"

namespace penumbra {

namespace {

// Rotation angle between the orientations of two unit quaternions.
double angleBetween(const Quaternion& a, const Quaternion& b) {
  return 2 * std::acos(std::min(1.0, std::abs(a.dotWith(b))));
}

Vec3 scaled(const Vec3& s, const Vec3& v) {
  return {s.x * v.x, s.y * v.y, s.z * v.z};
}

double largestAbs(const Vec3& v) {
  return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}

}  // namespace

Box3 transformedBounds(const std::vector<Polygon3>& polygons, const Transform& transform) {
  Box3 box;
  for (const Polygon3& polygon : polygons)
    for (const Vec3& p : polygon) box.extend(transform.applyToPoint(p));
  return box;
}

Box3 sweptBounds(const std::vector<Polygon3>& polygons, const TrsPose& a, const TrsPose& b) {
  Box3 box = transformedBounds(polygons, a.toTransform());
  box.extend(transformedBounds(polygons, b.toTransform()));
  const bool sameRotation = (a.rotate.w == b.rotate.w && a.rotate.x == b.rotate.x &&
                             a.rotate.y == b.rotate.y && a.rotate.z == b.rotate.z);
  if (sameRotation || box.isEmpty()) return box;
  Box3 local;
  for (const Polygon3& polygon : polygons)
    for (const Vec3& p : polygon) local.extend(p);
  const Vec3 c = local.center();
  double radius = 0;
  for (const Polygon3& polygon : polygons)
    for (const Vec3& p : polygon) radius = std::max(radius, length(p - c));
  // Within slerp's nearly-parallel branch (normalized lerp, under 3.7 degrees) the angle does not
  // grow uniformly with t: allow the whole step's angle on top of each part's.
  const double total = angleBetween(a.rotate, b.rotate);
  const double uneven = std::abs(a.rotate.dotWith(b.rotate)) > 0.999 ? total : 0;
  constexpr int kParts = 256;
  const auto poseAt = [&](int i) {
    const double t = double(i) / kParts;
    return TrsPose{lerp(a.translate, b.translate, t), slerp(a.rotate, b.rotate, t),
                   lerp(a.scale, b.scale, t)};
  };
  TrsPose from = poseAt(0);
  for (int i = 0; i < kParts; ++i) {
    const TrsPose to = poseAt(i + 1);
    const Vec3 centre = from.translate + from.rotate.toMatrix() * scaled(from.scale, c);
    const double drift = length(to.translate - from.translate) +
                         length(scaled(to.scale - from.scale, c)) +
                         (angleBetween(from.rotate, to.rotate) + uneven) *
                             std::max(length(scaled(from.scale, c)), length(scaled(to.scale, c)));
    const double reach = std::max(largestAbs(from.scale), largestAbs(to.scale)) * radius;
    Box3 part;
    part.extend(centre);
    box.extend(part.expanded(drift + reach));
    from = to;
  }
  return box;
}

Box3 sweptBounds(const SceneObject& object, double fromFrame, double toFrame) {
  if (!object.isDynamic()) return transformedBounds(object.polygons, object.transformAt(fromFrame));
  const double lo = std::min(fromFrame, toFrame), hi = std::max(fromFrame, toFrame);
  Box3 box = transformedBounds(object.polygons, object.transformAt(lo));
  box.extend(transformedBounds(object.polygons, object.transformAt(hi)));
  const std::vector<Keyframe>& keys = object.motion.keyframes();
  for (size_t k = 1; k < keys.size(); ++k) {
    const double start = std::max(lo, double(keys[k - 1].frame));
    const double end = std::min(hi, double(keys[k].frame));
    if (start >= end) continue;
    // Restricted to a sub-interval, the interpolation is the same kind between its ends' poses.
    box.extend(
        sweptBounds(object.polygons, object.motion.poseAt(start), object.motion.poseAt(end)));
  }
  return box;
}

Box3 reachBounds(const SceneObject& object) {
  if (!object.isDynamic())
    return transformedBounds(object.polygons, object.transform.toTransform());
  const std::vector<Keyframe>& keys = object.motion.keyframes();
  return sweptBounds(object, keys.front().frame, keys.back().frame);
}

Box3 reachBounds(const Scene& scene) {
  Box3 box;
  for (const SceneObject& object : scene.objects) box.extend(reachBounds(object));
  return box;
}

}  // namespace penumbra
