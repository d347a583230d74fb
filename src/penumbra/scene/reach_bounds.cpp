#include "penumbra/scene/reach_bounds.h"

#include <algorithm>
#include <cmath>

#include "penumbra/scene/scene.h"

namespace penumbra {

namespace {

bool sameLinear(const Mat3& a, const Mat3& b) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a.m[i][j] != b.m[i][j]) return false;
  return true;
}

// Largest factor by which `linear` can stretch a vector: bounded by its Frobenius norm (a rotation
// times a diagonal scale has exactly the largest |scale| as spectral norm; Frobenius is an upper
// bound that needs no eigen-solver).
double stretchBound(const Mat3& linear) {
  double sum = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) sum += linear.m[i][j] * linear.m[i][j];
  return std::sqrt(sum);
}

}  // namespace

Box3 transformedBounds(const std::vector<Polygon3>& polygons, const Transform& transform) {
  Box3 box;
  for (const Polygon3& polygon : polygons)
    for (const Vec3& p : polygon) box.extend(transform.applyToPoint(p));
  return box;
}

Box3 sweptBounds(const std::vector<Polygon3>& polygons, const Transform& a, const Transform& b) {
  Box3 box = transformedBounds(polygons, a);
  box.extend(transformedBounds(polygons, b));
  if (sameLinear(a.linear, b.linear)) return box;
  // Scale interpolates linearly per axis, so |S(t) p| <= max(|S_a|, |S_b|) |p|; slerp keeps
  // lengths; the translation runs along the segment between the two ends.
  double radius = 0;
  for (const Polygon3& polygon : polygons)
    for (const Vec3& p : polygon) radius = std::max(radius, length(p));
  radius *= std::max(stretchBound(a.linear), stretchBound(b.linear));
  Box3 path;
  path.extend(a.translation);
  path.extend(b.translation);
  box.extend(path.expanded(radius));
  return box;
}

Box3 reachBounds(const SceneObject& object) {
  if (!object.isDynamic())
    return transformedBounds(object.polygons, object.transform.toTransform());
  const std::vector<Keyframe>& keys = object.motion.keyframes();
  Box3 box = transformedBounds(object.polygons, keys.front().pose.toTransform());
  for (size_t k = 1; k < keys.size(); ++k)
    box.extend(
        sweptBounds(object.polygons, keys[k - 1].pose.toTransform(), keys[k].pose.toTransform()));
  return box;
}

Box3 reachBounds(const Scene& scene) {
  Box3 box;
  for (const SceneObject& object : scene.objects) box.extend(reachBounds(object));
  return box;
}

}  // namespace penumbra
