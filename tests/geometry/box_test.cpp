#include "penumbra/geometry/box.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <numeric>
#include <random>

namespace penumbra {
namespace {

Box3 boxOf(const Vec3& lo, const Vec3& hi) {
  Box3 box;
  box.extend(lo);
  box.extend(hi);
  return box;
}

// meetsSegment must not depend on the direction the segment is given in.
void expectMeets(const Box3& box, const Vec3& a, const Vec3& b, bool expected) {
  EXPECT_EQ(box.meetsSegment(a, b), expected) << "segment " << a << " -> " << b;
  EXPECT_EQ(box.meetsSegment(b, a), expected) << "segment " << b << " -> " << a;
  EXPECT_EQ(SegmentBoxTest(a, b).meets(box), expected) << "prepared " << a << " -> " << b;
  EXPECT_EQ(SegmentBoxTest(b, a).meets(box), expected) << "prepared " << b << " -> " << a;
}

// Distance from the closed segment ab to the box: the minimum of the convex function
// t -> distance(lerp(a, b, t), box) over [0, 1], by ternary search.
double segmentDistance(const Box3& box, const Vec3& a, const Vec3& b) {
  const auto f = [&](double t) { return distance(lerp(a, b, t), box); };
  double lo = 0, hi = 1;
  for (int i = 0; i < 200; ++i) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (f(m1) < f(m2))
      hi = m2;
    else
      lo = m1;
  }
  return std::min({f(0), f(1), f(lo), f(hi), f((lo + hi) / 2)});
}

// Exact brute force for segments with integer end points and an integer box: the set of t in [0, 1]
// where the segment is in the box is an interval whose ends are multiples of 1/|d_k| for some
// axis k, so if it is not empty it contains t = j / M for M the least common multiple of the
// non-zero |d_k|; each such point is tested in integer arithmetic.
using IntPoint = std::array<std::int64_t, 3>;
bool latticeSegmentMeetsBox(const IntPoint& a, const IntPoint& b, const IntPoint& lo,
                            const IntPoint& hi) {
  std::int64_t m = 1;
  for (int k = 0; k < 3; ++k)
    if (b[k] != a[k]) m = std::lcm(m, std::abs(b[k] - a[k]));
  for (std::int64_t j = 0; j <= m; ++j) {
    bool inside = true;
    for (int k = 0; k < 3 && inside; ++k) {
      // The point's coordinate times m: m * a + (b - a) * j.
      const std::int64_t c = m * a[k] + (b[k] - a[k]) * j;
      inside = m * lo[k] <= c && c <= m * hi[k];
    }
    if (inside) return true;
  }
  return false;
}

Vec3 toVec(const IntPoint& p, double scale) {
  return {double(p[0]) * scale, double(p[1]) * scale, double(p[2]) * scale};
}

TEST(Box3MeetsSegment, SegmentInsideCrossingOrMissing) {
  const Box3 box = boxOf({1, -1, 0}, {2, 3, 0.5});
  // Wholly inside.
  expectMeets(box, {1.2, 0, 0.1}, {1.8, 2, 0.4}, true);
  // One end inside, the other outside.
  expectMeets(box, {1.5, 1, 0.25}, {5, 7, 9}, true);
  // Crossing through, both ends outside, along each axis and diagonally.
  expectMeets(box, {0, 1, 0.25}, {3, 1, 0.25}, true);
  expectMeets(box, {1.5, -5, 0.25}, {1.5, 5, 0.25}, true);
  expectMeets(box, {1.5, 1, -1}, {1.5, 1, 1}, true);
  expectMeets(box, {0, -3, -1}, {3, 5, 1.5}, true);
  // Missing on each side of each axis: parallel to the box, just outside.
  expectMeets(box, {0.999, -2, 0.25}, {0.999, 4, 0.25}, false);
  expectMeets(box, {2.001, -2, 0.25}, {2.001, 4, 0.25}, false);
  expectMeets(box, {0, -1.001, 0.25}, {3, -1.001, 0.25}, false);
  expectMeets(box, {0, 3.001, 0.25}, {3, 3.001, 0.25}, false);
  expectMeets(box, {0, 1, -0.001}, {3, 1, -0.001}, false);
  expectMeets(box, {0, 1, 0.501}, {3, 1, 0.501}, false);
  // Missing on each side with no zero direction component.
  expectMeets(box, {0.5, -2, -1}, {0.9, 4, 1}, false);
  expectMeets(box, {2.1, -2, -1}, {2.5, 4, 1}, false);
  expectMeets(box, {0, -1.5, -1}, {3, -1.1, 1}, false);
  expectMeets(box, {0, 3.1, -1}, {3, 3.5, 1}, false);
  expectMeets(box, {0, -2, -1}, {3, 4, -0.1}, false);
  expectMeets(box, {0, -2, 0.6}, {3, 4, 1.5}, false);
  // The segment would cross the box if it were longer: it stops short on either side.
  expectMeets(box, {-3, 1, 0.25}, {0.9, 1, 0.25}, false);
  expectMeets(box, {2.1, 1, 0.25}, {7, 1, 0.25}, false);
  expectMeets(box, {-3, -9, -2}, {0.5, 0, -0.25}, false);
  // Its own bounding box overlaps the box but the segment passes the corner diagonally.
  expectMeets(boxOf({0, 0, 0}, {1, 1, 1}), {2.5, 0, 0.5}, {0, 2.5, 0.5}, false);
  expectMeets(boxOf({0, 0, 0}, {1, 1, 1}), {1.5, 0, 0.5}, {0, 1.5, 0.5}, true);
}

TEST(Box3MeetsSegment, TouchingFaceEdgeOrCornerCounts) {
  const Box3 box = boxOf({0, 0, 0}, {1, 1, 1});
  // Touching a face at one point: from outside, ending on the face.
  expectMeets(box, {-1, 0.5, 0.5}, {0, 0.5, 0.5}, true);
  expectMeets(box, {0.5, 2, 0.5}, {0.5, 1, 0.5}, true);
  // Touching a face at an interior point of the segment (the segment bounces off it).
  expectMeets(box, {0.5, 0.5, 2}, {0.5, 0.5, 1}, true);
  expectMeets(box, {-1, 0.5, 1.5}, {1, 0.5, 0.5}, true);
  // Grazing an edge from outside: the segment crosses the line x = y = 1 at (1, 1, 0.5) only.
  expectMeets(box, {2, 0, 0.5}, {0, 2, 0.5}, true);
  // Grazing a corner: (1 + s, 1 - s, 1 + s) is outside for every s but 0.
  expectMeets(box, {0, 2, 0}, {2, 0, 2}, true);
  expectMeets(box, {-1, -1, 1}, {1, 1, -1}, true);  // through the corner (0, 0, 0)
  // Ending at a corner, an edge point, a face point.
  expectMeets(box, {1, 1, 1}, {2, 2, 2}, true);
  expectMeets(box, {1, 0.5, 1}, {3, 0.5, 4}, true);
  expectMeets(box, {1, 0.25, 0.75}, {3, -1, 4}, true);
  // The same segments moved off by a little miss.
  expectMeets(box, {-1, 0.5, 0.5}, {-1e-12, 0.5, 0.5}, false);
  expectMeets(box, {2, 0, 0.5}, {1e-9, 2 + 1e-9, 0.5}, false);
  expectMeets(box, {0, 2, 1e-9}, {2, 0, 2 + 1e-9}, false);
  expectMeets(box, {1, 1, 1 + 1e-12}, {2, 2, 2}, false);
}

TEST(Box3MeetsSegment, DegenerateSegments) {
  const Box3 box = boxOf({-1, 0, 2}, {1, 0.5, 3});
  expectMeets(box, {0, 0.25, 2.5}, {0, 0.25, 2.5}, true);  // a point inside
  expectMeets(box, {1, 0.5, 3}, {1, 0.5, 3}, true);        // at a corner
  expectMeets(box, {0, 0, 2.5}, {0, 0, 2.5}, true);        // on a face
  expectMeets(box, {0, 0.25, 3.5}, {0, 0.25, 3.5}, false);
  expectMeets(box, {-1.5, 0.25, 2.5}, {-1.5, 0.25, 2.5}, false);
  expectMeets(box, {0, -1e-12, 2.5}, {0, -1e-12, 2.5}, false);
  expectMeets(box, {1 + 1e-12, 0.5, 3}, {1 + 1e-12, 0.5, 3}, false);
}

TEST(Box3MeetsSegment, AxisParallelSegmentsInAFacePlane) {
  const Box3 box = boxOf({0, 0, 0}, {1, 2, 3});
  // In the plane y = 0 (zero y component), crossing the face, inside it, or beside it.
  expectMeets(box, {0.2, 0, 0.3}, {0.8, 0, 0.9}, true);
  expectMeets(box, {-1, 0, 1}, {2, 0, 1}, true);
  expectMeets(box, {2, 0, 1}, {3, 0, 1}, false);
  expectMeets(box, {-1, 0, 4}, {2, 0, 4}, false);
  // In the plane x = 1 and z = 3 (two zero components): along the edge and beyond its ends.
  expectMeets(box, {1, -1, 3}, {1, 5, 3}, true);
  expectMeets(box, {1, 0.5, 3}, {1, 1.5, 3}, true);
  expectMeets(box, {1, 2, 3}, {1, 7, 3}, true);  // starts at the corner
  expectMeets(box, {1, 2.5, 3}, {1, 7, 3}, false);
  // The same lines just off the plane miss, whatever their extent in the other axes.
  expectMeets(box, {0.2, -1e-12, 0.3}, {0.8, -1e-12, 0.9}, false);
  expectMeets(box, {1 + 1e-12, -1, 3}, {1 + 1e-12, 5, 3}, false);
  expectMeets(box, {-5, 2.000001, -5}, {5, 2.000001, 5}, false);
  // Zero components inside the slab: only the other axes decide.
  expectMeets(box, {0.5, 1, -5}, {0.5, 1, 5}, true);
  expectMeets(box, {0.5, 1, 3.5}, {0.5, 1, 5}, false);
}

TEST(Box3MeetsSegment, EmptyBoxIsNeverMet) {
  const Box3 empty;
  ASSERT_TRUE(empty.isEmpty());
  expectMeets(empty, {0, 0, 0}, {0, 0, 0}, false);
  expectMeets(empty, {-1e300, -1e300, -1e300}, {1e300, 1e300, 1e300}, false);
  expectMeets(empty, {-1, 2, 3}, {4, -5, 6}, false);
  // Empty in one axis only (min > max in y): a segment through the other two slabs misses it.
  Box3 inverted = boxOf({0, 0, 0}, {1, 1, 1});
  inverted.min.y = 0.6;
  inverted.max.y = 0.4;
  ASSERT_TRUE(inverted.isEmpty());
  expectMeets(inverted, {0.5, -1, 0.5}, {0.5, 2, 0.5}, false);
  expectMeets(inverted, {0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}, false);
  // A single-point box is not empty and is met by segments through its point.
  const Box3 point = boxOf({0.5, 0.5, 0.5}, {0.5, 0.5, 0.5});
  expectMeets(point, {0, 0, 0}, {1, 1, 1}, true);
  expectMeets(point, {0, 0, 0}, {1, 1, 1.000001}, false);
}

TEST(Box3MeetsSegment, LatticeSegmentsAgreeWithExactBruteForce) {
  // Integer end points make touching a face, an edge or a corner common; the brute force is exact.
  // Scaling by a power of two keeps every coordinate exact.
  std::mt19937 rng(20240611);
  std::uniform_int_distribution<int> boxCoordinate(0, 3), offset(-2, 2);
  int met = 0, missed = 0;
  for (int i = 0; i < 20000; ++i) {
    IntPoint lo, hi, a, b;
    for (int k = 0; k < 3; ++k) {
      lo[k] = boxCoordinate(rng);
      hi[k] = lo[k] + boxCoordinate(rng);  // sometimes flat (lo == hi)
      // End points around the box: within two units of its sides.
      a[k] = (offset(rng) < 0 ? lo[k] : hi[k]) + offset(rng);
      b[k] = (offset(rng) < 0 ? lo[k] : hi[k]) + offset(rng);
    }
    if (i % 10 == 0) b = a;  // degenerate segments
    const bool expected = latticeSegmentMeetsBox(a, b, lo, hi);
    (expected ? met : missed) += 1;
    for (double scale : {1.0, 0.25, 1024.0}) {
      const Box3 box = boxOf(toVec(lo, scale), toVec(hi, scale));
      ASSERT_EQ(box.meetsSegment(toVec(a, scale), toVec(b, scale)), expected)
          << "box " << box.min << " " << box.max << " segment " << toVec(a, scale) << " "
          << toVec(b, scale);
      ASSERT_EQ(box.meetsSegment(toVec(b, scale), toVec(a, scale)), expected);
    }
  }
  // Both outcomes are well represented.
  EXPECT_GT(met, 4000);
  EXPECT_GT(missed, 4000);
}

TEST(Box3MeetsSegment, RandomSegmentsAgreeWithSamplingAndDistance) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-3, 3), size(0.01, 2), around(-1.5, 1.5);
  int decidedTrue = 0, decidedFalse = 0;
  for (int i = 0; i < 3000; ++i) {
    Box3 box;
    box.min = {u(rng), u(rng), u(rng)};
    box.max = box.min + Vec3{size(rng), size(rng), size(rng)};
    // End points near the box: up to 1.5 half-sizes plus 0.75 from its centre on each axis.
    const Vec3 c = box.center(), h = box.diagonal() * 0.5;
    const auto nearBox = [&] {
      return c + Vec3{h.x * around(rng), h.y * around(rng), h.z * around(rng)} +
             Vec3{around(rng), around(rng), around(rng)} * 0.5;
    };
    Vec3 a = nearBox(), b = nearBox();
    // Some segments parallel to an axis plane or to an axis.
    if (i % 7 == 1) b.y = a.y;
    if (i % 7 == 2) b.x = a.x, b.z = a.z;
    const bool meets = box.meetsSegment(a, b);
    EXPECT_EQ(box.meetsSegment(b, a), meets);
    // The prepared segment (its reciprocals made once) decides as the brute force does too.
    const bool prepared = SegmentBoxTest(a, b).meets(box);
    // A sample well inside the box (not within 1e-9 of its boundary) decides "meets".
    const Box3 shrunk = box.expanded(-1e-9);
    bool sampledInside = false;
    for (int k = 0; k <= 4000 && !sampledInside; ++k)
      sampledInside = shrunk.contains(lerp(a, b, k / 4000.0));
    // A clearly positive distance decides "misses".
    const double gap = segmentDistance(box, a, b);
    if (sampledInside) {
      ++decidedTrue;
      EXPECT_TRUE(meets) << "box " << box.min << " " << box.max << " segment " << a << " " << b;
      EXPECT_TRUE(prepared) << "box " << box.min << " " << box.max << " segment " << a << " " << b;
    } else if (gap > 1e-9) {
      ++decidedFalse;
      EXPECT_FALSE(meets) << "box " << box.min << " " << box.max << " segment " << a << " " << b
                          << " gap " << gap;
      EXPECT_FALSE(prepared) << "box " << box.min << " " << box.max << " segment " << a << " " << b;
    }
  }
  // The brute force decides almost every random case, both ways.
  EXPECT_GT(decidedTrue, 800);
  EXPECT_GT(decidedFalse, 800);
  EXPECT_GT(decidedTrue + decidedFalse, 2950);
}

}  // namespace
}  // namespace penumbra
