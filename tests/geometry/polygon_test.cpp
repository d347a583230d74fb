#include "penumbra/geometry/polygon.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <utility>

#include "penumbra/geometry/predicates.h"
#include "penumbra/geometry/triangulation.h"

namespace penumbra {
namespace {

const Polygon3 kUnitSquare{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
// An L shape (non-convex), area 3.
const Polygon3 kLShape{{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};

TEST(Polygon, NormalAreaCentroid) {
  EXPECT_EQ(newellNormal(kUnitSquare), (Vec3{0, 0, 2}));
  EXPECT_DOUBLE_EQ(area(kLShape), 3.0);
  const Vec3 c = centroid(kLShape);  // union of three unit squares at (.5,.5),(1.5,.5),(.5,1.5)
  EXPECT_NEAR(c.x, 2.5 / 3, 1e-15);
  EXPECT_NEAR(c.y, 2.5 / 3, 1e-15);
  const Plane plane = supportingPlane(kUnitSquare);
  EXPECT_EQ(plane.normal, (Vec3{0, 0, 1}));
  EXPECT_EQ(plane.offset, 0.0);
}

TEST(Polygon, ClipByPlaneKeepsFrontPart) {
  const Plane halfX = Plane::fromPointNormal({0.25, 0, 0}, {1, 0, 0});
  const Polygon3 clipped = clipByPlane(kUnitSquare, halfX);
  EXPECT_DOUBLE_EQ(area(clipped), 0.75);
  // Non-convex: clipping the L at x >= 0.5 leaves 2 - 0.5 + 0.5 ... = area of x in [0.5, 2].
  const Polygon3 clippedL = clipByPlane(kLShape, Plane::fromPointNormal({0.5, 0, 0}, {1, 0, 0}));
  EXPECT_DOUBLE_EQ(area(clippedL), 3.0 - 1.0);
  EXPECT_TRUE(clipByPlane(kUnitSquare, Plane::fromPointNormal({2, 0, 0}, {1, 0, 0})).empty());
}

TEST(Polygon, PlaneFrameIsRightHanded) {
  for (const Vec3& n : {Vec3{0, 0, 1}, Vec3{1, 0, 0}, Vec3{0, -1, 0}, normalize(Vec3{1, 2, 3})}) {
    const PlaneFrame f = PlaneFrame::fromPlane(Plane::fromPointNormal({1, 2, 3}, n), {1, 2, 3});
    EXPECT_NEAR(dot(cross(f.u, f.v), f.n), 1.0, 1e-15);
    const Vec3 p{4, -2, 7};
    const Vec3 back = f.toWorld(f.toLocal(p));
    // Round trip is exact for points on the plane only; project first.
    const Vec3 onPlane = Plane::fromPointNormal({1, 2, 3}, n).project(p);
    EXPECT_NEAR(distance(f.toWorld(f.toLocal(onPlane)), onPlane), 0, 1e-13);
    (void)back;
  }
}

TEST(PolygonDefect, AcceptsGoodPolygons) {
  EXPECT_FALSE(findPolygonDefect(kUnitSquare));
  EXPECT_FALSE(findPolygonDefect(kLShape));
}

TEST(PolygonDefect, RejectsEachDefect) {
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {1, 0, 0}})->find("fewer than 3"), std::string::npos);
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, 0, 0}})->find("fewer than 3"),
            std::string::npos);
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}})->find("zero area"),
            std::string::npos);
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0}})->find("non-planar"),
            std::string::npos);
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}})->find("self-inter"),
            std::string::npos);
  EXPECT_NE(findPolygonDefect({{0, 0, 0}, {std::nan(""), 0, 0}, {0, 1, 0}})->find("NaN"),
            std::string::npos);
}

// Every pair of edges, exactly: do two non-adjacent edges share a point? (The oracle for the sweep
// findPolygonDefect uses above 1,024 vertices.)
bool selfIntersectsByEveryPair(const Polygon3& polygon) {
  const size_t n = polygon.size();
  const auto at = [&](size_t i) { return Vec2{polygon[i % n].x, polygon[i % n].y}; };
  const auto within = [](const Vec2& p, const Vec2& q, const Vec2& r) {
    return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
           r.y <= std::max(p.y, q.y);
  };
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;
      const Vec2 a = at(i), b = at(i + 1), c = at(j), d = at(j + 1);
      const Sign o1 = orientation2d(a, b, c), o2 = orientation2d(a, b, d);
      const Sign o3 = orientation2d(c, d, a), o4 = orientation2d(c, d, b);
      if (o1 != o2 && o3 != o4 && o1 != Sign::kZero && o2 != Sign::kZero && o3 != Sign::kZero &&
          o4 != Sign::kZero)
        return true;
      if ((o1 == Sign::kZero && within(a, b, c)) || (o2 == Sign::kZero && within(a, b, d)) ||
          (o3 == Sign::kZero && within(c, d, a)) || (o4 == Sign::kZero && within(c, d, b)))
        return true;
    }
  return false;
}

// Above 1,024 vertices simplicity is checked by a sweep over the edges' x-intervals (a pass over
// every pair took 60 s for 100,000 vertices, in `penumbra info`): the same verdicts as every pair,
// on star-shaped polygons of 1,500 vertices, simple and with two vertices swapped, and a vertex
// folding back along its edge.
TEST(Polygon, ManyVerticesCheckedBySweepAsByEveryPair) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> radius(1, 2);
  const size_t n = 1500;
  Polygon3 star;
  for (size_t i = 0; i < n; ++i) {
    const double angle = 2 * M_PI * double(i) / double(n), r = radius(random);
    star.push_back({r * std::cos(angle), r * std::sin(angle), 0});
  }
  EXPECT_FALSE(selfIntersectsByEveryPair(star));
  EXPECT_FALSE(findPolygonDefect(star)) << *findPolygonDefect(star);
  int crossed = 0;
  for (int trial = 0; trial < 6; ++trial) {
    Polygon3 swapped = star;
    const size_t i = random() % n, j = (i + 2 + random() % 5) % n;
    std::swap(swapped[i], swapped[j]);
    const bool expected = selfIntersectsByEveryPair(swapped);
    const auto defect = findPolygonDefect(swapped);
    EXPECT_EQ(defect.has_value(), expected) << trial << ": " << (defect ? *defect : "none");
    if (defect) {
      EXPECT_NE(defect->find("self-intersecting"), std::string::npos) << *defect;
    }
    crossed += expected ? 1 : 0;
  }
  EXPECT_GT(crossed, 0);
  Polygon3 folded = star;
  folded.insert(folded.begin() + 11, folded[9]);  // 9, 10, back to 9's place, 11
  const auto defect = findPolygonDefect(folded);
  ASSERT_TRUE(defect);
  EXPECT_NE(defect->find("self-overlapping polygon: edges 9 and 10"), std::string::npos) << *defect;
}

TEST(Polygon, SegmentCrossesPolygonExcludesEndsOnItsPlane) {
  const Polygon3 square{{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
  const Plane plane = supportingPlane(square);
  const double tolerance = 1e-7;
  const auto crosses = [&](const Vec3& a, const Vec3& b) {
    return segmentCrossesPolygon(a, b, square, plane, tolerance);
  };
  EXPECT_TRUE(crosses({0, 0, 0}, {0, 0, 3}));
  EXPECT_TRUE(crosses({0, 0, 3}, {0.3, -0.9, 0}));
  EXPECT_FALSE(crosses({5, 5, 0}, {5, 5, 3}));
  EXPECT_FALSE(crosses({0, 0, 0}, {0, 0, 0.5}));  // short of it
  // Ending on its plane, from either side, or within the tolerance of it: not a crossing.
  EXPECT_FALSE(crosses({0, 0, 0}, {0.3, 0.2, 1}));
  EXPECT_FALSE(crosses({0.3, 0.2, 1.5}, {0.3, 0.2, 1}));
  EXPECT_FALSE(crosses({0, 0, 0}, {0.3, 0.2, 1 + 0.5 * tolerance}));
  EXPECT_TRUE(crosses({0, 0, 0}, {0.3, 0.2, 1 + 1e-3}));
  // Lying in its plane.
  EXPECT_FALSE(crosses({-0.9, -0.9, 1}, {0.9, 0.8, 1}));
}

// Tilted non-convex polygons against an oracle of their own: the crossing point found inside one
// of the triangles of their ear-clipped triangulation (barycentric coordinates), away from every
// edge by 1e-7.
TEST(Polygon, SegmentCrossesPolygonAgreesWithItsTriangles) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  const Polygon2 star = [] {
    Polygon2 loop;
    for (int k = 0; k < 10; ++k) {
      const double angle = k * std::numbers::pi / 5, radius = k % 2 ? 0.4 : 1.0;
      loop.push_back({radius * std::cos(angle), radius * std::sin(angle)});
    }
    return loop;
  }();
  int compared = 0, crossed = 0;
  for (int shape = 0; shape < 40; ++shape) {
    const Vec3 n = normalize(Vec3{unit(rng), unit(rng), unit(rng)});
    const PlaneFrame frame =
        PlaneFrame::fromPlane(Plane::fromPointNormal({}, n), Vec3{unit(rng), unit(rng), unit(rng)});
    Polygon3 polygon;
    for (const Vec2& q : star) polygon.push_back(frame.toWorld(q));
    if (shape % 2) polygon = {polygon[0], polygon[2], polygon[3], polygon[5]};  // a quad, dented
    const Plane plane = supportingPlane(polygon);
    const auto triangles = triangulate(polygon);
    ASSERT_FALSE(triangles.empty());
    for (int i = 0; i < 500; ++i) {
      const Vec3 a = frame.origin + Vec3{unit(rng), unit(rng), unit(rng)} * 1.5;
      const Vec3 b = frame.origin + Vec3{unit(rng), unit(rng), unit(rng)} * 1.5;
      const double da = plane.signedDistance(a), db = plane.signedDistance(b);
      if (std::abs(da) < 1e-6 || std::abs(db) < 1e-6) continue;
      bool expected = false, ambiguous = false;
      if ((da > 0) != (db > 0)) {
        const Vec3 p = a + (b - a) * (da / (da - db));
        for (const auto& t : triangles) {
          const Vec3 &u = polygon[t[0]], &v = polygon[t[1]], &w = polygon[t[2]];
          const double whole = dot(cross(v - u, w - u), plane.normal);
          const std::array<double, 3> weights{dot(cross(v - p, w - p), plane.normal) / whole,
                                              dot(cross(w - p, u - p), plane.normal) / whole,
                                              dot(cross(u - p, v - p), plane.normal) / whole};
          const double least = std::min({weights[0], weights[1], weights[2]});
          if (std::abs(least) < 1e-7) ambiguous = true;
          if (least > 0) expected = true;
        }
      }
      if (ambiguous) continue;
      ++compared;
      crossed += expected;
      EXPECT_EQ(segmentCrossesPolygon(a, b, polygon, plane, 1e-9), expected) << shape << " " << i;
    }
  }
  EXPECT_GT(compared, 19000);
  EXPECT_GT(crossed, 1500);
}

TEST(Polygon2, ContainsAndSignedArea) {
  const Polygon2 square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_DOUBLE_EQ(signedArea(square), 1.0);
  EXPECT_TRUE(containsPoint(square, {0.5, 0.5}));
  EXPECT_FALSE(containsPoint(square, {1.5, 0.5}));
}

}  // namespace
}  // namespace penumbra
