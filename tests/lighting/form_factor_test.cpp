#include "penumbra/lighting/form_factor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace penumbra {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

// Closed forms by direct integration of cosθ₁cosθ₂/(πr²) over the rectangle (Howell's catalogue),
// independent of Lambert's contour formula under test. The point is at the origin with normal +z.
// Parallel: rectangle [0,a]x[0,b] at height c, facing down.
double parallelCornerFormFactor(double a, double b, double c) {
  const double ac = std::hypot(a, c), bc = std::hypot(b, c);
  return (a / ac * std::atan(b / ac) + b / bc * std::atan(a / bc)) / kTwoPi;
}
// Perpendicular: rectangle in the plane y = c, x in [0,a], z in [0,b], facing the point.
double perpendicularFormFactor(double a, double b, double c) {
  const double bc = std::hypot(b, c);
  return (std::atan(a / c) - c / bc * std::atan(a / bc)) / kTwoPi;
}

TEST(FormFactor, ParallelRectangleMatchesClosedForm) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> size(0.01, 10);
  for (int i = 0; i < 1000; ++i) {
    const double a = size(rng), b = size(rng), c = size(rng);
    // Counter-clockwise seen from below (from the point): normal -z.
    const Polygon3 light{{0, 0, c}, {0, b, c}, {a, b, c}, {a, 0, c}};
    const double expected = parallelCornerFormFactor(a, b, c);
    EXPECT_NEAR(pointToPolygonFormFactor({0, 0, 0}, {0, 0, 1}, light), expected, 1e-12 * expected)
        << a << " " << b << " " << c;
  }
}

TEST(FormFactor, CentredParallelSquareIsSumOfFourCorners) {
  const Polygon3 light{{-1, -1, 2}, {-1, 1, 2}, {1, 1, 2}, {1, -1, 2}};
  const double expected = 4 * parallelCornerFormFactor(1, 1, 2);
  EXPECT_NEAR(pointToPolygonFormFactor({0, 0, 0}, {0, 0, 1}, light), expected, 1e-12 * expected);
}

TEST(FormFactor, PerpendicularRectangleMatchesClosedForm) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> size(0.01, 10);
  for (int i = 0; i < 1000; ++i) {
    const double a = size(rng), b = size(rng), c = size(rng);
    // Front side towards the point: normal -y.
    const Polygon3 light{{0, c, 0}, {a, c, 0}, {a, c, b}, {0, c, b}};
    ASSERT_LT(newellNormal(light).y, 0);
    const double expected = perpendicularFormFactor(a, b, c);
    // When b << c both the closed form and Lambert's sum are differences of two terms of size
    // atan(a/c)/2π that nearly cancel, so neither is accurate beyond a few ulps of that term:
    // the tolerance is 1e-12 relative plus 4 ulps of the cancelling term (condition number aware).
    const double cancellingTerm = std::atan(a / c) / kTwoPi;
    const double tolerance = 1e-12 * expected + 4 * std::numeric_limits<double>::epsilon() * cancellingTerm;
    EXPECT_NEAR(pointToPolygonFormFactor({0, 0, 0}, {0, 0, 1}, light), expected, tolerance)
        << a << " " << b << " " << c;
  }
}

TEST(FormFactor, HoleSubtracts) {
  const Polygon3 outer{{-1, -1, 1}, {-1, 1, 1}, {1, 1, 1}, {1, -1, 1}};
  const Polygon3 holeCw{{-0.5, -0.5, 1}, {0.5, -0.5, 1}, {0.5, 0.5, 1}, {-0.5, 0.5, 1}};
  const Polygon3 inner{{-0.5, -0.5, 1}, {-0.5, 0.5, 1}, {0.5, 0.5, 1}, {0.5, -0.5, 1}};
  const Vec3 p{0.1, 0.2, 0}, n{0, 0, 1};
  EXPECT_NEAR(pointToPolygonFormFactor(p, n, outer) + pointToPolygonFormFactor(p, n, holeCw),
              pointToPolygonFormFactor(p, n, outer) - pointToPolygonFormFactor(p, n, inner), 1e-15);
  EXPECT_GT(pointToPolygonFormFactor(p, n, inner), 0);
}

TEST(FormFactor, InfinitePlaneLimitIsOne) {
  const double big = 1e7;
  const Polygon3 light{{-big, -big, 1}, {-big, big, 1}, {big, big, 1}, {big, -big, 1}};
  EXPECT_NEAR(pointToPolygonFormFactor({0, 0, 0}, {0, 0, 1}, light), 1.0, 1e-6);
}

}  // namespace
}  // namespace penumbra
