#include "orbit_camera.h"

#include <algorithm>
#include <cmath>

namespace penumbra::viewer {
namespace {

// Rotation of v about the unit axis k by `angle` (Rodrigues).
Vec3 rotate(const Vec3& v, const Vec3& k, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + cross(k, v) * s + k * (dot(k, v) * (1 - c));
}

}  // namespace

void OrbitCamera::orbit(double yawRadians, double pitchRadians) {
  const Vec3 up = normalize(current_.up);
  Vec3 offset = current_.eye - current_.target;
  offset = rotate(offset, up, yawRadians);
  const Vec3 right = normalize(cross(-offset, up));
  // Stop 5 degrees short of looking straight along up: lookAt needs up and the view apart.
  const double elevation = std::asin(std::clamp(dot(normalize(offset), up), -1.0, 1.0));
  const double limit = std::acos(-1.0) / 2 - 0.0873;
  const double pitch = std::clamp(elevation + pitchRadians, -limit, limit) - elevation;
  offset = rotate(offset, right, -pitch);
  current_.eye = current_.target + offset;
}

void OrbitCamera::zoom(double factor) {
  current_.eye = current_.target + (current_.eye - current_.target) * factor;
}

bool OrbitCamera::isModified() const {
  return current_.eye.x != base_.eye.x || current_.eye.y != base_.eye.y ||
         current_.eye.z != base_.eye.z;
}

}  // namespace penumbra::viewer
