#include "penumbra/geometry/transform.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

namespace penumbra {
namespace {

void expectNear(const Vec3& a, const Vec3& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(Transform, TrsAppliesScaleThenRotateThenTranslate) {
  const Transform t = Transform::fromTrs(
      {1, 2, 3}, Quaternion::fromAxisAngle({0, 0, 1}, std::numbers::pi / 2), {2, 1, 1});
  // (1,0,0) -> scale (2,0,0) -> rotate 90° about z (0,2,0) -> translate (1,4,3)
  expectNear(t.applyToPoint({1, 0, 0}), {1, 4, 3}, 1e-15);
  expectNear(t.applyToVector({1, 0, 0}), {0, 2, 0}, 1e-15);
}

TEST(Transform, InverseUndoesRandomTransforms) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-10, 10);
  for (int i = 0; i < 100; ++i) {
    const Transform t = Transform::fromTrs(
        {u(rng), u(rng), u(rng)}, Quaternion::fromAxisAngle({u(rng), u(rng), u(rng)}, u(rng)),
        {1 + std::abs(u(rng)), 0.5 + std::abs(u(rng)), -1 - std::abs(u(rng))});
    const Vec3 p{u(rng), u(rng), u(rng)};
    expectNear(t.inverse().applyToPoint(t.applyToPoint(p)), p, 1e-11);
    expectNear((t * t.inverse()).applyToPoint(p), p, 1e-11);
    EXPECT_TRUE(t.isReflection());  // one negative scale factor
  }
}

TEST(Quaternion, SlerpHalfwayIsHalfTheAngle) {
  const Quaternion a = Quaternion::identity();
  const Quaternion b = Quaternion::fromAxisAngle({0, 1, 0}, std::numbers::pi / 2);
  const Quaternion h = slerp(a, b, 0.5);
  const Quaternion expected = Quaternion::fromAxisAngle({0, 1, 0}, std::numbers::pi / 4);
  EXPECT_NEAR(std::abs(h.dotWith(expected)), 1.0, 1e-15);
  EXPECT_NEAR(std::abs(slerp(a, b, 0).dotWith(a)), 1.0, 1e-15);
  EXPECT_NEAR(std::abs(slerp(a, b, 1).dotWith(b)), 1.0, 1e-15);
}

}  // namespace
}  // namespace penumbra
