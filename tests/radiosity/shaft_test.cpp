#include "penumbra/radiosity/shaft.h"

#include <gtest/gtest.h>

#include <random>

namespace penumbra {
namespace {

Box3 randomBox(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> position(-10, 10), extent(0, 3);
  Box3 b;
  const Vec3 p{position(rng), position(rng), position(rng)};
  b.extend(p);
  b.extend(p + Vec3{extent(rng), extent(rng), extent(rng)});
  return b;
}

Vec3 pointIn(const Box3& b, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> t(0, 1);
  const Vec3 d = b.diagonal();
  return b.min + Vec3{d.x * t(rng), d.y * t(rng), d.z * t(rng)};
}

// The shaft must contain the convex hull of its boxes: every segment between them.
TEST(Shaft, ContainsEverySegmentBetweenItsBoxes) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> t(0, 1);
  for (int trial = 0; trial < 500; ++trial) {
    const Box3 a = randomBox(rng), b = randomBox(rng);
    const Shaft shaft(a, b);
    EXPECT_LE(shaft.planeCount(), 8);
    for (int k = 0; k < 20; ++k) {
      const Vec3 p = pointIn(a, rng), q = pointIn(b, rng);
      const Vec3 x = p + (q - p) * t(rng);
      // 1e-9: rounding of plane offsets for coordinates of size 10.
      ASSERT_TRUE(shaft.contains(x, 1e-9)) << trial;
      Box3 tiny;
      tiny.extend(x);
      ASSERT_TRUE(shaft.mayIntersect(tiny));
    }
  }
}

TEST(Shaft, CutsOffTheHullCorners) {
  // Two unit boxes on a diagonal: the hull's other corners are outside the shaft.
  Box3 a, b;
  a.extend({0, 0, 0});
  a.extend({1, 1, 1});
  b.extend({4, 4, 0});
  b.extend({5, 5, 1});
  const Shaft shaft(a, b);
  EXPECT_EQ(shaft.planeCount(), 2);
  EXPECT_FALSE(shaft.contains({4.5, 0.5, 0.5}));
  EXPECT_FALSE(shaft.contains({0.5, 4.5, 0.5}));
  EXPECT_TRUE(shaft.contains({2.5, 2.5, 0.5}));
  Box3 away;
  away.extend({4, 0, 0});
  away.extend({5, 1, 1});
  EXPECT_FALSE(shaft.mayIntersect(away));
  Box3 across;
  across.extend({2, 2, -1});
  across.extend({3, 3, 2});
  EXPECT_TRUE(shaft.mayIntersect(across));
}

}  // namespace
}  // namespace penumbra
