#include "penumbra/render/view_projection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace penumbra {
namespace {

void expectMatrixNear(const Mat4& actual, const double (&expected)[4][4], double tolerance) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(actual.m[i][j], expected[i][j], tolerance) << i << j;
}

TEST(LookAt, CanonicalCameraIsTheIdentity) {
  const double identity[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  expectMatrixNear(lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}), identity, 0);
}

TEST(LookAt, HandComputedMatrix) {
  // Eye (1, 2, 3) looking along +x with up +y: side = forward x up = (0, 0, 1), up = (0, 1, 0),
  // back = -forward = (-1, 0, 0); translations are -row . eye.
  const double expected[4][4] = {{0, 0, 1, -3}, {0, 1, 0, -2}, {-1, 0, 0, 1}, {0, 0, 0, 1}};
  expectMatrixNear(lookAt({1, 2, 3}, {5, 2, 3}, {0, 1, 0}), expected, 1e-15);
}

TEST(LookAt, MapsEyeToOriginAndTargetOntoTheNegativeZAxis) {
  const Vec3 eye{1, 2, 3}, target{-2, 0.5, 7};
  const Mat4 view = lookAt(eye, target, {0, 1, 0});
  const Vec4 e = view.transformPoint(eye);
  EXPECT_NEAR(e.x, 0, 1e-14);
  EXPECT_NEAR(e.y, 0, 1e-14);
  EXPECT_NEAR(e.z, 0, 1e-14);
  const Vec4 t = view.transformPoint(target);
  EXPECT_NEAR(t.x, 0, 1e-14);
  EXPECT_NEAR(t.y, 0, 1e-14);
  EXPECT_NEAR(t.z, -distance(eye, target), 1e-14);
}

TEST(LookAt, UpAlongTheViewAxisStillGivesARotation) {
  const Mat4 view = lookAt({0, 10, 0}, {0, 0, 0}, {0, 1, 0});  // straight down, up = +y
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) EXPECT_TRUE(std::isfinite(view.m[i][j]));
  const Vec4 t = view.transformPoint({0, 0, 0});
  EXPECT_NEAR(t.z, -10, 1e-14);
}

TEST(Perspective, HandComputedMatrix) {
  // fovY 90° -> focal length 1; aspect 2; near 1, far 3.
  const double expected[4][4] = {{0.5, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, -2, -3}, {0, 0, -1, 0}};
  expectMatrixNear(perspective(90, 2, 1, 3), expected, 1e-15);
}

TEST(Perspective, NearAndFarMapToWindowDepthZeroAndOne) {
  const Camera camera{.eye = {0, 0, 0},
                      .target = {0, 0, -1},
                      .up = {0, 1, 0},
                      .fovYDegrees = 60,
                      .width = 10,
                      .height = 10};
  const Mat4 vp = viewProjection(camera, 100, 50, {.near = 0.5, .far = 20}).combined();
  EXPECT_NEAR(projectToPixel(vp, {0, 0, -0.5}, 100, 50).depth, 0, 1e-15);
  EXPECT_NEAR(projectToPixel(vp, {0, 0, -20}, 100, 50).depth, 1, 1e-15);
}

TEST(Perspective, InfiniteFarPlaneHandComputedMatrix) {
  const double expected[4][4] = {{0.5, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, -1, -2}, {0, 0, -1, 0}};
  expectMatrixNear(infinitePerspective(90, 2, 1), expected, 1e-15);
}

TEST(Perspective, InfiniteFarPlaneKeepsEveryFinitePointInFrontOfDepthOne) {
  const Camera camera{.eye = {0, 0, 0},
                      .target = {0, 0, -1},
                      .up = {0, 1, 0},
                      .fovYDegrees = 60,
                      .width = 10,
                      .height = 10};
  const Mat4 vp =
      viewProjection(camera, 64, 64, {.near = 0.1, .far = 0, .infiniteFar = true}).combined();
  EXPECT_NEAR(projectToPixel(vp, {0, 0, -0.1}, 64, 64).depth, 0, 1e-15);
  for (double d : {1.0, 1e3, 1e6}) {
    const double depth = projectToPixel(vp, {0, 0, -d}, 64, 64).depth;
    EXPECT_LT(depth, 1) << d;
    EXPECT_NEAR(depth, 1 - 0.1 / d, 1e-15) << d;
  }
  // A direction (w = 0 input) lands exactly on depth 1: where z-fail volumes put their far caps.
  const Vec4 clip = vp * Vec4(0.3, -0.2, -1, 0);
  EXPECT_DOUBLE_EQ(clip.z / clip.w, 1);
}

TEST(ViewProjection, PointsOnTheViewAxisProjectToTheImageCentre) {
  const Camera camera{.eye = {1, 2, 3},
                      .target = {-2, 0.5, 7},
                      .up = {0, 1, 0},
                      .fovYDegrees = 45,
                      .width = 640,
                      .height = 480};
  for (const ClipRange& clip : {ClipRange{.near = 0.1, .far = 100, .infiniteFar = false},
                                ClipRange{.near = 0.1, .far = 0, .infiniteFar = true}}) {
    const Mat4 vp = viewProjection(camera, 320, 200, clip).combined();
    for (double t : {0.5, 1.0, 7.0}) {
      const PixelPosition p = projectToPixel(vp, lerp(camera.eye, camera.target, t), 320, 200);
      EXPECT_TRUE(p.inFront);
      EXPECT_NEAR(p.x, 160, 1e-9);
      EXPECT_NEAR(p.y, 100, 1e-9);
    }
    EXPECT_FALSE(projectToPixel(vp, lerp(camera.eye, camera.target, -1.0), 320, 200).inFront);
  }
}

TEST(ViewProjection, EdgeOfTheFieldOfViewIsTheEdgeOfTheImage) {
  const Camera camera{.eye = {0, 0, 0},
                      .target = {0, 0, -1},
                      .up = {0, 1, 0},
                      .fovYDegrees = 50,
                      .width = 1,
                      .height = 1};
  const Mat4 vp = viewProjection(camera, 200, 100, {.near = 0.1, .far = 10}).combined();
  const double halfAngle = 25 * std::numbers::pi / 180;
  // Up in the world is up in the image: row 0 is the top.
  const PixelPosition top = projectToPixel(vp, {0, std::tan(halfAngle) * 3, -3}, 200, 100);
  EXPECT_NEAR(top.y, 0, 1e-12);
  EXPECT_NEAR(top.x, 100, 1e-12);
  // Aspect 2: the horizontal half-width at depth 3 is twice the vertical one.
  const PixelPosition right = projectToPixel(vp, {2 * std::tan(halfAngle) * 3, 0, -3}, 200, 100);
  EXPECT_NEAR(right.x, 200, 1e-12);
  EXPECT_NEAR(right.y, 50, 1e-12);
}

TEST(ClipRangeFor, EnclosesTheBoxAndNeverGoesBehindTheEye) {
  Camera camera{.eye = {0, 0, 10},
                .target = {0, 0, 0},
                .up = {0, 1, 0},
                .fovYDegrees = 50,
                .width = 1,
                .height = 1};
  Box3 box;
  box.extend({-1, -1, -1});
  box.extend({1, 1, 1});
  const ClipRange outside = clipRangeFor(camera, box);
  EXPECT_GT(outside.near, 0);
  EXPECT_LT(outside.near, 9);
  EXPECT_GT(outside.far, 11);
  EXPECT_FALSE(outside.infiniteFar);
  camera.eye = {0, 0, 0.5};  // inside the box
  const ClipRange inside = clipRangeFor(camera, box);
  EXPECT_GT(inside.near, 0);
  EXPECT_LE(inside.near, 1e-3);
  EXPECT_GT(inside.far, 1.5);
}

}  // namespace
}  // namespace penumbra
