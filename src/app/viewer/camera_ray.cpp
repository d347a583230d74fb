#include "camera_ray.h"

#include <cmath>
#include <numbers>

namespace penumbra::viewer {

Vec3 cameraRayDirection(const Camera& camera, int width, int height, double x, double y) {
  const Vec3 forward = normalize(camera.target - camera.eye);
  const Vec3 right = normalize(cross(forward, camera.up));
  const Vec3 up = cross(right, forward);
  const double tanHalfFovY = std::tan(camera.fovYDegrees * std::numbers::pi / 360);
  const double aspect = double(width) / height;
  const double ndcX = 2 * x / width - 1, ndcY = 1 - 2 * y / height;
  return normalize(forward + right * (ndcX * tanHalfFovY * aspect) + up * (ndcY * tanHalfFovY));
}

}  // namespace penumbra::viewer
