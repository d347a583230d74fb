#include "object_drag.h"

#include <cmath>
#include <numbers>

namespace penumbra::viewer {

Transform translatedBy(const Transform& transform, const Vec3& offset) {
  return {transform.linear, transform.translation + offset};
}

Transform rotatedAboutUp(const Transform& transform, const Vec3& centre, double degrees) {
  // The scene loader's own construction of { "axis": [0, 1, 0], "degrees": d } (see the header).
  const Mat3 r = Quaternion::fromAxisAngle(kWorldUp, degrees * std::numbers::pi / 180).toMatrix();
  return {r * transform.linear, r * (transform.translation - centre) + centre};
}

ObjectDrag::ObjectDrag(int object, const Transform& start, const Vec3& grabbed,
                       const Vec3& planeNormal)
    : object_(object), start_(start), grabbed_(grabbed), normal_(normalize(planeNormal)) {}

std::optional<Transform> ObjectDrag::transformFor(const Vec3& origin, const Vec3& direction,
                                                  double maxDistance) const {
  const double facing = dot(direction, normal_);
  if (facing == 0) return std::nullopt;
  const double t = dot(grabbed_ - origin, normal_) / facing;
  if (!(t > 0) || !std::isfinite(t)) return std::nullopt;
  const Vec3 offset = origin + direction * t - grabbed_;
  if (!(length(offset) <= maxDistance)) return std::nullopt;
  return translatedBy(start_, offset);
}

}  // namespace penumbra::viewer
