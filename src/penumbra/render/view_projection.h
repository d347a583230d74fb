#pragma once
// Camera matrices in OpenGL conventions: right-handed eye space looking down -z, clip space with
// NDC depth in [-1, 1] mapped to window depth [0, 1] (glDepthRange default).

#include "penumbra/geometry/box.h"
#include "penumbra/render/mat4.h"
#include "penumbra/scene/camera.h"

namespace penumbra {

// World -> eye space. Precondition: eye != target; up != 0. When up is parallel to the viewing
// direction (a camera looking straight down with up = +y is a legitimate scene file), another
// axis is used for up instead of producing NaNs.
Mat4 lookAt(const Vec3& eye, const Vec3& target, const Vec3& up);

// Eye -> clip space. Preconditions: 0 < fovYDegrees < 180, aspect = width / height > 0,
// 0 < near < far. Points at eye depth `near` map to window depth 0, at `far` to 1.
Mat4 perspective(double fovYDegrees, double aspect, double near, double far);

// The far -> infinity limit of perspective(): nothing is ever clipped by a far plane, which z-fail
// shadow volumes need (their caps are projected to infinity). Window depth is
// 1 - near / eyeDepth: < 1 for every finite point, and exactly 1 for directions (w = 0).
// Preconditions as for perspective(), without far. Pair with GL_DEPTH_CLAMP when drawing points
// at infinity, so depth rounding cannot push them past 1.
Mat4 infinitePerspective(double fovYDegrees, double aspect, double near);

struct ClipRange {
  double near = 0.1;
  double far = 1000;  // ignored when infiniteFar
  bool infiniteFar = false;
};

// Near and far planes that enclose `bounds` as seen from the camera: far just beyond the farthest
// corner, near just before the nearest one but no closer than far * 1e-4 (with a 24-bit depth
// buffer that keeps depth resolution near 1e-3 of far at the back of the scene, the price of not
// clipping geometry right in front of a camera placed inside a room). An empty box gives
// ClipRange{}; a box entirely behind the camera gives a small range in front of it.
ClipRange clipRangeFor(const Camera& camera, const Box3& bounds);

struct ViewProjection {
  Mat4 view;
  Mat4 projection;
  Mat4 combined() const { return projection * view; }
};

// The camera's matrices for a render of width x height pixels (aspect from the render size, not
// from camera.width / camera.height). Preconditions: width, height > 0; the camera is valid for
// lookAt() and perspective().
ViewProjection viewProjection(const Camera& camera, int width, int height, const ClipRange& clip);

// Where a world point lands in a width x height render: x right and y down in pixels (pixel
// (i, j) covers [i, i+1) x [j, j+1), row 0 at the top, as in Image), window depth in [0, 1] when
// inside the clip range. `inFront` is false for points at or behind the eye plane (w <= 0), for
// which x, y and depth are meaningless.
struct PixelPosition {
  double x = 0, y = 0, depth = 0;
  bool inFront = false;
};
PixelPosition projectToPixel(const Mat4& viewProjection, const Vec3& p, int width, int height);

}  // namespace penumbra
