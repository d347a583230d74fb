#include "penumbra/spatial/shaft.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

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

// containsBox is conservative the other way: a box it says is inside has every point inside, and
// every box within it is one mayIntersect admits (the movers' blocks rely on both, exactly).
TEST(Shaft, ContainsBoxOnlyWhenEveryPointIsInsideAndAdmitsEveryBoxWithin) {
  std::mt19937_64 rng(11);
  int inside = 0, straddling = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Box3 a = randomBox(rng), b = randomBox(rng);
    const Shaft shaft(a, b);
    // Boxes around a point of the segment between the ends: some inside, some across a face.
    std::uniform_real_distribution<double> t(0, 1), size(0, 2);
    const Vec3 p = pointIn(a, rng), q = pointIn(b, rng);
    const Vec3 centre = p + (q - p) * t(rng);
    const Vec3 half{size(rng), size(rng), size(rng)};
    const Box3 box{centre - half * 0.5, centre + half * 0.5};
    if (!shaft.containsBox(box)) {
      straddling += shaft.mayIntersect(box);
      continue;
    }
    ++inside;
    for (int k = 0; k < 20; ++k) ASSERT_TRUE(shaft.contains(pointIn(box, rng))) << trial;
    for (int k = 0; k < 20; ++k) {
      Box3 within;
      within.extend(pointIn(box, rng));
      within.extend(pointIn(box, rng));
      ASSERT_TRUE(shaft.mayIntersect(within)) << trial;
    }
    // Its own corners as degenerate boxes, the extreme case of a box within.
    for (const Vec3& corner : {box.min, box.max}) {
      Box3 point;
      point.extend(corner);
      ASSERT_TRUE(shaft.mayIntersect(point)) << trial;
    }
  }
  // Both outcomes occur often enough to have been tested.
  EXPECT_GT(inside, 200);
  EXPECT_GT(straddling, 200);
  EXPECT_FALSE(Shaft(Box3{{0, 0, 0}, {1, 1, 1}}, Box3{{5, 0, 0}, {6, 1, 1}})
                   .containsBox(Box3{{2, 0.5, 0.5}, {3, 1.5, 0.6}}));
  EXPECT_TRUE(Shaft(Box3{{0, 0, 0}, {1, 1, 1}}, Box3{{5, 0, 0}, {6, 1, 1}})
                  .containsBox(Box3{{2, 0.25, 0.25}, {3, 0.75, 0.75}}));
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

// A random convex polygon: a triangle or a parallelogram-like convex quad in a random plane.
Polygon3 randomPolygon(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> position(-5, 5), extent(0.2, 3), unit(-1, 1);
  const Vec3 centre{position(rng), position(rng), position(rng)};
  Vec3 n{unit(rng), unit(rng), unit(rng)};
  if (length(n) < 1e-3) n = {0, 0, 1};
  n = normalize(n);
  const Vec3 u = normalize(std::abs(n.x) < 0.9 ? cross(n, {1, 0, 0}) : cross(n, {0, 1, 0}));
  const Vec3 v = cross(n, u);
  const double a = extent(rng), b = extent(rng);
  if (rng() % 2) return {centre, centre + u * a, centre + v * b};
  const double skew = 0.5 * unit(rng);
  return {centre, centre + u * a, centre + u * (a + skew) + v * b, centre + u * skew + v * b};
}

Vec3 pointOn(const Polygon3& p, std::mt19937_64& rng) {
  // Random convex combination of the vertices: a point of the convex polygon (not uniform).
  std::uniform_real_distribution<double> t(0, 1);
  double weights[4], sum = 0;
  for (size_t i = 0; i < p.size(); ++i) sum += weights[i] = -std::log(1 - t(rng));
  Vec3 x{0, 0, 0};
  for (size_t i = 0; i < p.size(); ++i) x += p[i] * (weights[i] / sum);
  return x;
}

// Slab test: does the segment pq meet the box?
bool segmentHitsBox(const Vec3& p, const Vec3& q, const Box3& box) {
  double t0 = 0, t1 = 1;
  const double o[3] = {p.x, p.y, p.z}, d[3] = {q.x - p.x, q.y - p.y, q.z - p.z};
  const double lo[3] = {box.min.x, box.min.y, box.min.z}, hi[3] = {box.max.x, box.max.y, box.max.z};
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0) {
      if (o[k] < lo[k] || o[k] > hi[k]) return false;
      continue;
    }
    double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return false;
  }
  return true;
}

// Polygon-to-polygon shafts against a brute-force oracle: segments between random points of the
// two polygons. A box that some segment meets must be reported (the shaft is conservative); the
// shaft must contain every such segment point; and the polygon shaft must be at least as tight
// as the box-to-box shaft of the same polygons, and reject most boxes no segment meets.
TEST(Shaft, PolygonShaftAgainstSegmentSampling) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> t(0, 1);
  int missedByAllSegments = 0, rejectedByPolygonShaft = 0, rejectedByBoxShaft = 0;
  int polygonShafts = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Polygon3 a = randomPolygon(rng), b = randomPolygon(rng);
    const Shaft shaft(a, b);
    Box3 ba, bb;
    for (const Vec3& p : a) ba.extend(p);
    for (const Vec3& p : b) bb.extend(p);
    const Shaft boxShaft(ba, bb);
    polygonShafts += shaft.isPolygonShaft();
    std::vector<std::pair<Vec3, Vec3>> segments;
    for (int k = 0; k < 400; ++k) segments.push_back({pointOn(a, rng), pointOn(b, rng)});
    for (const auto& [p, q] : segments)
      // 1e-9: rounding of plane offsets for coordinates of size 10.
      ASSERT_TRUE(shaft.contains(p + (q - p) * t(rng), 1e-9)) << trial;
    for (int k = 0; k < 20; ++k) {
      Box3 box;
      const Vec3 corner = ba.center() + (bb.center() - ba.center()) * t(rng) +
                          Vec3{t(rng) - 0.5, t(rng) - 0.5, t(rng) - 0.5} * 6.0;
      box.extend(corner);
      box.extend(corner + Vec3{t(rng), t(rng), t(rng)} * 0.5);
      bool hit = false;
      for (const auto& [p, q] : segments) hit = hit || segmentHitsBox(p, q, box);
      if (hit) {
        ASSERT_TRUE(shaft.mayIntersect(box)) << trial;
        ASSERT_TRUE(boxShaft.mayIntersect(box)) << trial;
      } else {
        ++missedByAllSegments;
        rejectedByPolygonShaft += !shaft.mayIntersect(box);
        rejectedByBoxShaft += !boxShaft.mayIntersect(box);
      }
      // A box entirely outside the polygon shaft is met by no segment (the converse above).
      if (!shaft.mayIntersect(box)) {
        EXPECT_FALSE(hit);
      }
    }
  }
  std::printf("boxes no segment meets: %d; rejected by polygon shafts %d, by box shafts %d\n",
              missedByAllSegments, rejectedByPolygonShaft, rejectedByBoxShaft);
  EXPECT_GT(polygonShafts, 290);  // random polygons are almost never coplanar
  EXPECT_GE(rejectedByPolygonShaft, rejectedByBoxShaft);
  // Boxes met by no sampled segment may still graze the hull; most must be rejected.
  EXPECT_GT(rejectedByPolygonShaft, missedByAllSegments / 2);
}

// Facing unit squares one apart: the shaft is the unit cube; a box inside is reported, boxes
// beside the cube (inside the hull box of a tilted pair, outside the hull) are not.
TEST(Shaft, PolygonShaftOfFacingSquares) {
  const Polygon3 floor{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const Polygon3 ceiling{{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}};
  const Shaft shaft(floor, ceiling);
  EXPECT_TRUE(shaft.isPolygonShaft());
  EXPECT_EQ(shaft.planeCount(), 6);
  Box3 inside;
  inside.extend({0.4, 0.4, 0.4});
  inside.extend({0.6, 0.6, 0.6});
  EXPECT_TRUE(shaft.mayIntersect(inside));
  // A sheared pair: the ceiling moved by 1 in x. The hull box spans x in [0, 2]; the corner
  // region near (1.8, 0.5, 0.1) is inside the box shaft's hull box but outside the hull.
  const Polygon3 shifted{{1, 0, 1}, {1, 1, 1}, {2, 1, 1}, {2, 0, 1}};
  const Shaft sheared(floor, shifted);
  Box3 corner;
  corner.extend({1.7, 0.4, 0.05});
  corner.extend({1.8, 0.6, 0.15});
  EXPECT_FALSE(sheared.mayIntersect(corner));
  Box3 middle;
  middle.extend({0.9, 0.4, 0.45});
  middle.extend({1.1, 0.6, 0.55});
  EXPECT_TRUE(sheared.mayIntersect(middle));
  // Coplanar polygons have no volume between them: the box shaft of their bounds is used.
  const Polygon3 beside{{2, 0, 0}, {3, 0, 0}, {3, 1, 0}, {2, 1, 0}};
  EXPECT_FALSE(Shaft(floor, beside).isPolygonShaft());
}

}  // namespace
}  // namespace penumbra
