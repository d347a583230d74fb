#include "penumbra/geometry/triangulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>

#include "penumbra/geometry/predicates.h"

namespace penumbra {
namespace {

Vec3 triangleNormal(const Polygon3& p, const std::array<int, 3>& t) {
  return cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
}

// Checks the header's postconditions that do not need a point-in-polygon oracle.
void expectValidTriangulation(const Polygon3& polygon, bool expectAllVertices = true) {
  SCOPED_TRACE(::testing::Message() << "polygon with " << polygon.size() << " vertices");
  const auto triangles = triangulate(polygon);
  const Vec3 normal = newellNormal(polygon);
  double sum = 0;
  std::set<int> used;
  for (const auto& t : triangles) {
    for (int i : t) {
      ASSERT_GE(i, 0);
      ASSERT_LT(i, int(polygon.size()));
      used.insert(i);
    }
    const Vec3 tn = triangleNormal(polygon, t);
    // Orientation kept: each triangle faces the same way as the polygon, and is not degenerate.
    EXPECT_GT(dot(tn, normal), 0) << t[0] << " " << t[1] << " " << t[2];
    sum += 0.5 * length(tn);
  }
  EXPECT_NEAR(sum, area(polygon), 1e-12 * area(polygon));
  if (expectAllVertices) {
    EXPECT_EQ(triangles.size(), polygon.size() - 2);
    EXPECT_EQ(used.size(), polygon.size());
  }
}

// Interiors are disjoint and cover the polygon: every random point of the plane lies strictly
// inside at most one triangle, and inside one exactly when it is inside the polygon.
void expectTiling(const Polygon3& polygon, std::mt19937_64& rng, int samples = 2000) {
  const PlaneFrame frame = PlaneFrame::fromPlane(supportingPlane(polygon), polygon[0]);
  Polygon2 flat;
  for (const Vec3& p : polygon) flat.push_back(frame.toLocal(p));
  double minX = 1e300, maxX = -1e300, minY = 1e300, maxY = -1e300;
  for (const Vec2& q : flat) {
    minX = std::min(minX, q.x), maxX = std::max(maxX, q.x);
    minY = std::min(minY, q.y), maxY = std::max(maxY, q.y);
  }
  const auto triangles = triangulate(polygon);
  std::uniform_real_distribution<double> ux(minX, maxX), uy(minY, maxY);
  for (int s = 0; s < samples; ++s) {
    const Vec2 q{ux(rng), uy(rng)};
    int inside = 0;
    for (const auto& t : triangles) {
      if (orientation2d(flat[t[0]], flat[t[1]], q) == Sign::kPositive &&
          orientation2d(flat[t[1]], flat[t[2]], q) == Sign::kPositive &&
          orientation2d(flat[t[2]], flat[t[0]], q) == Sign::kPositive)
        ++inside;
    }
    ASSERT_LE(inside, 1);
    // Points on a triangle edge count in no triangle; they are measure zero for random samples.
    EXPECT_EQ(inside == 1, containsPoint(flat, q)) << q.x << " " << q.y;
  }
}

// Places a 2D loop in a tilted plane far from the origin.
Polygon3 embed(const std::vector<Vec2>& loop, const Vec3& offset = {3, -2, 5},
               const Vec3& axis = normalize(Vec3{1, 2, 3})) {
  const PlaneFrame frame = PlaneFrame::fromPlane(Plane::fromPointNormal(offset, axis), offset);
  Polygon3 out;
  for (const Vec2& q : loop) out.push_back(frame.toWorld(q));
  return out;
}

Polygon3 flat(const std::vector<Vec2>& loop) {
  Polygon3 out;
  for (const Vec2& q : loop) out.push_back({q.x, q.y, 0});
  return out;
}

const std::vector<Vec2> kL{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
const std::vector<Vec2> kU{{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};

std::vector<Vec2> comb(int teeth) {
  // A base bar with `teeth` spikes pointing up; many reflex vertices on the same line y = 1.
  std::vector<Vec2> loop{{0, 0}, {double(2 * teeth - 1), 0}};
  for (int k = teeth - 1; k >= 0; --k) {
    const double x = 2 * k;
    loop.push_back({x + 1, 1});
    loop.push_back({x + 1, 4});
    loop.push_back({x, 4});
    if (k > 0) loop.push_back({x, 1});
  }
  return loop;
}

TEST(Triangulation, TriangleAndSquare) {
  const Polygon3 triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const auto t = triangulate(triangle);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_GT(dot(triangleNormal(triangle, t[0]), Vec3{0, 0, 1}), 0);
  expectValidTriangulation(flat({{0, 0}, {1, 0}, {1, 1}, {0, 1}}));
}

TEST(Triangulation, DegenerateInputGivesNothing) {
  EXPECT_TRUE(triangulate({}).empty());
  EXPECT_TRUE(triangulate({{0, 0, 0}, {1, 0, 0}}).empty());
  EXPECT_TRUE(triangulate({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}).empty());
}

TEST(Triangulation, NonConvexShapes) {
  std::mt19937_64 rng(7);
  for (const auto& loop : {kL, kU, comb(1), comb(2), comb(7)}) {
    expectValidTriangulation(flat(loop));
    expectValidTriangulation(embed(loop));
    expectTiling(flat(loop), rng);
    expectTiling(embed(loop), rng);
  }
}

TEST(Triangulation, ClockwiseInputKeepsItsOwnOrientation) {
  // Reversed loops face -z; the triangles must face -z too.
  for (auto loop : {kL, kU, comb(4)}) {
    std::reverse(loop.begin(), loop.end());
    const Polygon3 polygon = flat(loop);
    expectValidTriangulation(polygon);
    for (const auto& t : triangulate(polygon)) EXPECT_LT(triangleNormal(polygon, t).z, 0);
  }
}

TEST(Triangulation, EveryAxisAndSign) {
  // The polygon's normal along +-x, +-y, +-z exercises every projection choice.
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {1.0, -1.0}) {
      Vec3 n;
      n[axis] = sign;
      expectValidTriangulation(embed(kU, {1, 2, 3}, n));
    }
  }
}

TEST(Triangulation, CollinearVertices) {
  // A square with a vertex in the middle of every edge and three on one edge.
  expectValidTriangulation(
      flat({{0, 0}, {0.5, 0}, {1, 0}, {1.5, 0}, {2, 0}, {2, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}}));
  // A triangle whose long edge carries 9 collinear vertices: every diagonal must end at the apex.
  std::vector<Vec2> fan;
  for (int i = 0; i <= 10; ++i) fan.push_back({double(i), 0});
  fan.push_back({5, 3});
  expectValidTriangulation(flat(fan));
  expectValidTriangulation(embed(fan));
  // An L with collinear vertices on the reflex edges: diagonals must not pass through them.
  const std::vector<Vec2> l{{0, 0}, {4, 0}, {4, 1}, {3, 1}, {2, 1}, {1, 1},
                            {1, 2}, {1, 3}, {1, 4}, {0, 4}, {0, 2}};
  expectValidTriangulation(flat(l));
  std::mt19937_64 rng(11);
  expectTiling(flat(l), rng);
  expectTiling(flat(fan), rng);
  // Exactly collinear vertices in 3D on a tilted plane: the projection must keep them collinear
  // (rotating into a PlaneFrame would round them off the line).
  Polygon3 tilted;
  for (int i = 0; i <= 6; ++i) tilted.push_back(Vec3{1, 3, 7} * (0.125 * i) + Vec3{1e3, 0, 0});
  tilted.push_back(Vec3{0.1, 1.3, 0.0} + Vec3{1e3, 0, 0});
  expectValidTriangulation(tilted);
  tilted.insert(tilted.begin() + 3, tilted[2]);  // and a repeated vertex among them
  expectValidTriangulation(tilted, /*expectAllVertices=*/false);
}

TEST(Triangulation, RepeatedVerticesAreSkipped) {
  const Polygon3 p{{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}};
  const auto triangles = triangulate(p);
  EXPECT_EQ(triangles.size(), 2u);
  expectValidTriangulation(p, /*expectAllVertices=*/false);
}

TEST(Triangulation, RandomStarShapedPolygons) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> unit(0, 1);
  int tested = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 3 + int(unit(rng) * 60);
    std::vector<double> angles(n);
    for (double& a : angles) a = unit(rng) * 2 * std::numbers::pi;
    std::sort(angles.begin(), angles.end());
    std::vector<Vec2> loop;
    for (double a : angles) {
      const double r = 0.05 + unit(rng) * (trial % 2 == 0 ? 1.0 : 1e3);
      loop.push_back({r * std::cos(a), r * std::sin(a)});
    }
    if (std::abs(signedArea(loop)) == 0) continue;
    const Polygon3 polygon =
        embed(loop, Vec3{unit(rng), unit(rng), unit(rng)} * 1e3,
              normalize(Vec3{unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5}));
    if (findPolygonDefect(polygon)) continue;  // sorted angles can still give a near-fold
    expectValidTriangulation(polygon);
    if (trial % 10 == 0) expectTiling(polygon, rng, 500);
    ++tested;
  }
  EXPECT_GT(tested, 150);
}

TEST(Triangulation, RandomStarShapedWithCollinearRuns) {
  // Star-shaped loops on the integer grid with vertices inserted at edge midpoints: exactly
  // collinear triples everywhere, exact in doubles.
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<int> radius(2, 20);
  int tested = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const int n = 3 + trial % 17;
    std::vector<Vec2> corners;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * std::numbers::pi * k / n;
      const int r = radius(rng);
      corners.push_back({std::round(2 * r * std::cos(a)), std::round(2 * r * std::sin(a))});
    }
    std::vector<Vec2> loop;
    for (int k = 0; k < n; ++k) {
      const Vec2 &a = corners[k], &b = corners[(k + 1) % n];
      loop.push_back(a);
      if (trial % 3 != 0) loop.push_back({(a.x + b.x) / 2, (a.y + b.y) / 2});
    }
    const Polygon3 polygon = flat(loop);
    if (findPolygonDefect(polygon) || withoutRepeatedVertices(polygon).size() != polygon.size())
      continue;
    expectValidTriangulation(polygon);
    expectTiling(polygon, rng, 300);
    ++tested;
  }
  EXPECT_GT(tested, 60);
}

}  // namespace
}  // namespace penumbra
