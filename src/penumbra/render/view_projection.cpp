#include "penumbra/render/view_projection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "penumbra/base/check.h"

namespace penumbra {

Mat4 lookAt(const Vec3& eye, const Vec3& target, const Vec3& up) {
  CHECK(!(eye == target));
  const Vec3 forward = normalize(target - eye);
  Vec3 side = cross(forward, up);
  if (squaredLength(side) <= 1e-24 * squaredLength(up)) {
    // Up along the view axis: take the world axis least aligned with the view instead.
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    int best = 0;
    for (int i = 1; i < 3; ++i) {
      if (std::abs(forward[i]) < std::abs(forward[best])) best = i;
    }
    side = cross(forward, axes[best]);
  }
  side = normalize(side);
  const Vec3 trueUp = cross(side, forward);
  Mat4 r;
  const Vec3 rows[3] = {side, trueUp, -forward};
  for (int i = 0; i < 3; ++i) {
    r.m[i][0] = rows[i].x;
    r.m[i][1] = rows[i].y;
    r.m[i][2] = rows[i].z;
    r.m[i][3] = -dot(rows[i], eye);
  }
  return r;
}

namespace {

double focalLength(double fovYDegrees) {
  CHECK(fovYDegrees > 0 && fovYDegrees < 180);
  return 1 / std::tan(fovYDegrees * std::numbers::pi / 360);
}

}  // namespace

Mat4 perspective(double fovYDegrees, double aspect, double near, double far) {
  CHECK_GT(aspect, 0);
  CHECK_GT(near, 0);
  CHECK_GT(far, near);
  const double f = focalLength(fovYDegrees);
  Mat4 r;
  r.m[0][0] = f / aspect;
  r.m[1][1] = f;
  r.m[2][2] = (far + near) / (near - far);
  r.m[2][3] = 2 * far * near / (near - far);
  r.m[3][2] = -1;
  r.m[3][3] = 0;
  return r;
}

Mat4 infinitePerspective(double fovYDegrees, double aspect, double near) {
  CHECK_GT(aspect, 0);
  CHECK_GT(near, 0);
  const double f = focalLength(fovYDegrees);
  Mat4 r;
  r.m[0][0] = f / aspect;
  r.m[1][1] = f;
  r.m[2][2] = -1;
  r.m[2][3] = -2 * near;
  r.m[3][2] = -1;
  r.m[3][3] = 0;
  return r;
}

ClipRange clipRangeFor(const Camera& camera, const Box3& bounds) {
  if (bounds.isEmpty()) return {};
  const Vec3 forward = normalize(camera.target - camera.eye);
  double nearest = std::numeric_limits<double>::infinity();
  double farthest = -std::numeric_limits<double>::infinity();
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p{(corner & 1) ? bounds.max.x : bounds.min.x,
                 (corner & 2) ? bounds.max.y : bounds.min.y,
                 (corner & 4) ? bounds.max.z : bounds.min.z};
    const double depth = dot(p - camera.eye, forward);
    nearest = std::min(nearest, depth);
    farthest = std::max(farthest, depth);
  }
  ClipRange clip;
  if (!(farthest > 0)) {
    clip.far = 1;
    clip.near = 1e-4;
    return clip;
  }
  // Margins so that geometry exactly on the box is not clipped by rounding.
  clip.far = farthest * 1.01;
  clip.near = std::max(nearest * 0.99, clip.far * 1e-4);
  return clip;
}

ViewProjection viewProjection(const Camera& camera, int width, int height, const ClipRange& clip) {
  CHECK_GT(width, 0);
  CHECK_GT(height, 0);
  const double aspect = static_cast<double>(width) / height;
  ViewProjection vp;
  vp.view = lookAt(camera.eye, camera.target, camera.up);
  vp.projection = clip.infiniteFar ? infinitePerspective(camera.fovYDegrees, aspect, clip.near)
                                   : perspective(camera.fovYDegrees, aspect, clip.near, clip.far);
  return vp;
}

PixelPosition projectToPixel(const Mat4& viewProjection, const Vec3& p, int width, int height) {
  const Vec4 clip = viewProjection.transformPoint(p);
  PixelPosition r;
  r.inFront = clip.w > 0;
  if (!r.inFront) return r;
  const double ndcX = clip.x / clip.w, ndcY = clip.y / clip.w, ndcZ = clip.z / clip.w;
  r.x = (ndcX + 1) * 0.5 * width;
  r.y = (1 - ndcY) * 0.5 * height;  // GL's window y grows upwards; image rows grow downwards
  r.depth = (ndcZ + 1) * 0.5;
  return r;
}

}  // namespace penumbra
