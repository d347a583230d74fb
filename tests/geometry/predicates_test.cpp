#include "penumbra/geometry/predicates.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

TEST(Orientation3d, PositiveOnTheSideTheNormalPointsTo) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};  // normal (b-a)x(c-a) = +z
  EXPECT_EQ(orientation3d(a, b, c, {0.2, 0.2, 1}), Sign::kPositive);
  EXPECT_EQ(orientation3d(a, b, c, {0.2, 0.2, -1}), Sign::kNegative);
  EXPECT_EQ(orientation3d(a, b, c, {5, -7, 0}), Sign::kZero);
}

TEST(Orientation3d, ExactForNearlyCoplanarPoints) {
  // d is off the plane by one unit in the last place: a naive double determinant gets it wrong
  // at this magnitude, the filtered exact predicate does not.
  const Vec3 a{1e8, 1e8, 0}, b{1e8 + 1, 1e8, 0}, c{1e8, 1e8 + 1, 0};
  EXPECT_EQ(orientation3d(a, b, c, {3e8, 3e8, 0}), Sign::kZero);
  EXPECT_EQ(orientation3d(a, b, c, {3e8, 3e8, 1e-300}), Sign::kPositive);
  EXPECT_EQ(orientation3d(a, b, c, {3e8, 3e8, -1e-300}), Sign::kNegative);
}

TEST(Orientation2d, LeftTurnIsPositive) {
  EXPECT_EQ(orientation2d({0, 0}, {1, 0}, {1, 1}), Sign::kPositive);
  EXPECT_EQ(orientation2d({0, 0}, {1, 0}, {1, -1}), Sign::kNegative);
  EXPECT_EQ(orientation2d({0, 0}, {1, 1}, {0.5, 0.5}), Sign::kZero);
  // 0.1 + 0.2 != 0.3 in doubles: the exact answer for the doubles given is not collinear.
  EXPECT_EQ(orientation2d({0, 0}, {0.1, 0.1}, {0.3, 0.1 + 0.2}), Sign::kPositive);
}

}  // namespace
}  // namespace penumbra
