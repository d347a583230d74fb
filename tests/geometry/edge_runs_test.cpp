// Clipping run by run must give what clipping vertex by vertex gives, bit for bit: the exact
// reference and the discontinuity mesh rely on one answer whichever path a polygon takes.

#include "penumbra/geometry/edge_runs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace penumbra {
namespace {

// A disc of n vertices in the plane y = height, optionally with a wavy (non-convex) rim.
Polygon3 disc(int n, double radius, double height, double wave) {
  Polygon3 loop;
  for (int k = 0; k < n; ++k) {
    const double angle = 2 * M_PI * k / n;
    const double r = radius * (1 + wave * std::sin(7 * angle));
    loop.push_back({r * std::cos(angle), height, r * std::sin(angle)});
  }
  return loop;
}

// Clips by a sequence of planes both ways and expects identical loops after every plane.
void expectSameClipping(const Polygon3& polygon, const std::vector<Plane>& planes) {
  Polygon3 plain = polygon, byRuns, next;
  std::vector<VertexRun> runs = edgeRuns(polygon), nextRuns;
  const Polygon3* from = &polygon;
  for (const Plane& plane : planes) {
    plain = clipByPlane(plain, plane);
    clipByPlane(*from, runs, plane, next, nextRuns);
    std::swap(byRuns, next);
    std::swap(runs, nextRuns);
    from = &byRuns;
    ASSERT_EQ(plain.size(), byRuns.size());
    for (size_t i = 0; i < plain.size(); ++i) {
      EXPECT_EQ(plain[i].x, byRuns[i].x);
      EXPECT_EQ(plain[i].y, byRuns[i].y);
      EXPECT_EQ(plain[i].z, byRuns[i].z);
    }
    for (const VertexRun& run : runs)  // carried runs still bound their vertices
      for (size_t c = run.begin; c < run.end; ++c) EXPECT_TRUE(run.box.contains(byRuns[c]));
  }
}

TEST(EdgeRuns, SmallPolygonsHaveNone) {
  EXPECT_TRUE(edgeRuns(disc(2 * int(kVertexRun), 1, 0, 0)).empty());
  EXPECT_FALSE(edgeRuns(disc(2 * int(kVertexRun) + 1, 1, 0, 0)).empty());
}

TEST(EdgeRuns, RunsCoverEveryEdge) {
  const Polygon3 loop = disc(1000, 1, 0, 0.1);
  const std::vector<VertexRun> runs = edgeRuns(loop);
  size_t next = 0;
  for (const VertexRun& run : runs) {
    EXPECT_EQ(run.begin, next);
    for (size_t c = run.begin; c <= run.end; ++c)
      EXPECT_TRUE(run.box.contains(loop[c % loop.size()]));
    next = run.end;
  }
  EXPECT_EQ(next, loop.size());
}

TEST(EdgeRuns, ClippingByRunsEqualsClippingVertexByVertex) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  int cut = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 33 + int(random() % 1500);
    const Polygon3 polygon = disc(n, 0.3 + 0.2 * unit(random), unit(random), trial % 2 ? 0.2 : 0);
    // A narrow cone from a point below, as the exact reference clips occluders: four side planes
    // through an apex and a far cap, and a few planes at random.
    const Vec3 apex{0.5 * unit(random), -2, 0.5 * unit(random)};
    const Vec3 target{0.4 * unit(random), 1, 0.4 * unit(random)};
    const double half = 0.01 + 0.1 * std::abs(unit(random));
    std::vector<Plane> planes;
    const Vec3 corners[4] = {target + Vec3{-half, 0, -half}, target + Vec3{half, 0, -half},
                             target + Vec3{half, 0, half}, target + Vec3{-half, 0, half}};
    for (int i = 0; i < 4; ++i) {
      Vec3 normal = cross(corners[i] - apex, corners[(i + 1) % 4] - apex);
      if (dot(normal, target - apex) < 0) normal = -normal;
      planes.push_back(Plane{normal, dot(normal, apex)});
    }
    planes.push_back(Plane::fromPointNormal(target, {0, -1, 0}));
    for (int i = 0; i < 2; ++i)
      planes.push_back(Plane::fromPointNormal({unit(random), unit(random), unit(random)},
                                              {unit(random), unit(random), unit(random)}));
    if (trial % 5 == 0) std::swap(planes[0], planes[5]);
    expectSameClipping(polygon, planes);
    cut += clipByPlane(polygon, planes[0]).size() != polygon.size();
  }
  EXPECT_GT(cut, 100);  // the planes do cut
}

TEST(EdgeRuns, PlanesThroughVerticesAndAlongEdges) {
  // Vertices exactly on the plane (signed distance 0 counts as in front) and a plane containing
  // a whole run: the runs' boxes touch the plane, so these are decided vertex by vertex.
  Polygon3 square;
  for (int i = 0; i < 100; ++i) square.push_back({i / 100.0, 0, 0});
  for (int i = 0; i < 100; ++i) square.push_back({1, 0, i / 100.0});
  for (int i = 0; i < 100; ++i) square.push_back({1 - i / 100.0, 0, 1});
  for (int i = 0; i < 100; ++i) square.push_back({0, 0, 1 - i / 100.0});
  expectSameClipping(square, {Plane{{1, 0, 0}, 0.5}, Plane{{0, 0, -1}, -1}, Plane{{-1, 0, 0}, 0},
                              Plane{{0, 0, 1}, 0.37}, Plane{{1, 0, 1}, 0.5}});
}

}  // namespace
}  // namespace penumbra
