#include "penumbra/spatial/ray_caster.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>

namespace penumbra {
namespace {

// Builds PosedScenes directly, the way poseAt() fills them.
class SceneBuilder {
 public:
  SceneBuilder() {
    scene_.materials.push_back(Material{"white", {0.5, 0.5, 0.5}, {}, false});
    scene_.materials.push_back(Material{"lamp", {0, 0, 0}, {10, 10, 10}, false});
  }
  PolygonId add(const Polygon3& vertices, bool light = false) {
    WorldPolygon p;
    p.id = PolygonId(scene_.polygons.size());
    p.material = light ? 1 : 0;
    p.vertices = vertices;
    p.plane = supportingPlane(vertices);
    p.area = area(vertices);
    p.bounds = boundingBox(vertices);
    p.isLight = light;
    if (light) scene_.lights.push_back(p.id);
    scene_.bounds.extend(p.bounds);
    scene_.polygons.push_back(std::move(p));
    indexObjects(scene_);
    return scene_.polygons.back().id;
  }
  const PosedScene& scene() const { return scene_; }

 private:
  PosedScene scene_;
};

// Axis-aligned rectangle [x0,x1] x [y0,y1] at height z, counter-clockwise seen from +z.
Polygon3 rectangleZ(double x0, double x1, double y0, double y1, double z, const Vec3& shift = {}) {
  return {Vec3{x0, y0, z} + shift, Vec3{x1, y0, z} + shift, Vec3{x1, y1, z} + shift,
          Vec3{x0, y1, z} + shift};
}

TEST(RayCaster, HitsTheClosestPolygonAtTheRightT) {
  SceneBuilder b;
  const PolygonId lower = b.add(rectangleZ(-1, 1, -1, 1, 1));
  const PolygonId upper = b.add(rectangleZ(-1, 1, -1, 1, 2));
  const RayCaster caster(b.scene());
  EXPECT_EQ(caster.triangleCount(), 4);

  const auto hit = caster.intersect({0.3, 0.2, 0}, {0, 0, 2}, 0, 10);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->polygon, lower);
  EXPECT_DOUBLE_EQ(hit->t, 0.5);  // t in units of the (non-unit) direction
  EXPECT_EQ(hit->point, (Vec3{0.3, 0.2, 1}));

  // tMin skips the lower square; tMax stops short of both.
  const auto second = caster.intersect({0.3, 0.2, 0}, {0, 0, 2}, 0.6, 10);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->polygon, upper);
  EXPECT_DOUBLE_EQ(second->t, 1.0);
  EXPECT_FALSE(caster.intersect({0.3, 0.2, 0}, {0, 0, 2}, 0, 0.4));
  // Infinite tMax, oblique direction, from above (back sides are hit too).
  const auto oblique = caster.intersect({0, 0, 0}, {0.5, 0.25, 1}, 0, INFINITY);
  ASSERT_TRUE(oblique);
  EXPECT_EQ(oblique->polygon, lower);
  EXPECT_NEAR(oblique->t, 1.0, 1e-15);
  EXPECT_NEAR(distance(oblique->point, {0.5, 0.25, 1}), 0, 1e-15);
  const auto down = caster.intersect({0.1, 0.1, 5}, {0, 0, -1}, 0, INFINITY);
  ASSERT_TRUE(down);
  EXPECT_EQ(down->polygon, upper);
  EXPECT_DOUBLE_EQ(down->t, 3.0);
  // Misses: beside the squares, pointing away.
  EXPECT_FALSE(caster.intersect({1.5, 0, 0}, {0, 0, 1}, 0, INFINITY));
  EXPECT_FALSE(caster.intersect({0, 0, 0}, {0, 0, -1}, 0, INFINITY));
  // The ignored polygon is transparent.
  const auto skipping = caster.intersect({0.3, 0.2, 0}, {0, 0, 1}, 0, INFINITY, lower);
  ASSERT_TRUE(skipping);
  EXPECT_EQ(skipping->polygon, upper);
}

TEST(RayCaster, MapsTrianglesOfNonConvexPolygonsBackToPolygonIds) {
  SceneBuilder b;
  const Polygon3 l{{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  std::vector<PolygonId> ids;
  b.add({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});  // zero area: not hittable, but keeps its id slot
  for (int k = 0; k < 5; ++k) {
    Polygon3 shifted = l;
    for (Vec3& v : shifted) v += Vec3{0, 0, double(k + 1)};
    ids.push_back(b.add(shifted));
  }
  const RayCaster caster(b.scene());
  EXPECT_EQ(caster.triangleCount(), 5 * 4);
  for (int k = 0; k < 5; ++k) {
    // Through the arm of each L (only L number k is above the start point).
    const auto hit = caster.intersect({0.5, 1.5, k + 0.5}, {0, 0, 1}, 0, INFINITY);
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->polygon, ids[k]);
  }
  // Through the notch: nothing.
  EXPECT_FALSE(caster.intersect({1.5, 1.5, -1}, {0, 0, 1}, 0, INFINITY));
}

TEST(RayCaster, OcclusionExcludesEndpointsOnPolygons) {
  SceneBuilder b;
  b.add(rectangleZ(-1, 1, -1, 1, 1));
  b.add(rectangleZ(-1, 1, -1, 1, 2));
  const RayCaster caster(b.scene());
  EXPECT_TRUE(caster.isOccluded({0, 0, 0}, {0, 0, 3}));
  EXPECT_FALSE(caster.isOccluded({5, 5, 0}, {5, 5, 3}));
  EXPECT_FALSE(caster.isOccluded({0, 0, 0}, {0, 0, 0}));
  // A segment ending exactly on a polygon is not blocked by it, from either side ...
  EXPECT_FALSE(caster.isOccluded({0, 0, 0}, {0.3, 0.2, 1}));
  EXPECT_FALSE(caster.isOccluded({0.3, 0.2, 1.5}, {0.3, 0.2, 1}));
  // ... but one going through it is.
  EXPECT_TRUE(caster.isOccluded({0, 0, 0}, {0.3, 0.2, 2}));
  // Starting on one polygon and ending on the next: nothing in between.
  EXPECT_FALSE(caster.isOccluded({0.3, 0.2, 1}, {-0.4, 0.9, 2}));
  EXPECT_TRUE(caster.isOccluded({0.3, 0.2, 1}, {-0.4, 0.9, 2.5}));
  // Just short of / just past a polygon, well outside the tolerance.
  ASSERT_LT(caster.epsilon(), 1e-4);
  EXPECT_FALSE(caster.isOccluded({0, 0, 0}, {0, 0, 1 - 1e-3}));
  EXPECT_TRUE(caster.isOccluded({0, 0, 0}, {0, 0, 1 + 1e-3}));
  // Both endpoints in a polygon's plane: the segment lies in the polygon, it is not blocked.
  EXPECT_FALSE(caster.isOccluded({-0.9, -0.9, 1}, {0.9, 0.8, 1}));
}

TEST(RayCaster, GrazingSegmentsDoNotHitTheirOwnSurfaces) {
  // A receiver floor and a light on a far wall: segments leave the floor at tiny angles, where a
  // parametric epsilon would let float self-hits through.
  SceneBuilder b;
  b.add(rectangleZ(-10, 10, -10, 10, 0));
  b.add({{10, -1, 0}, {10, 1, 0}, {10, 1, 2}, {10, -1, 2}}, /*light=*/true);
  const RayCaster caster(b.scene());
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p{-9.9 + 19 * unit(rng), -9.9 + 19.8 * unit(rng), 0};
    const Vec3 y{10, -1 + 2 * unit(rng), 1e-6 + 1e-3 * unit(rng)};
    EXPECT_FALSE(caster.isOccluded(p, y)) << p << " " << y;
  }
}

TEST(RayCaster, WatertightAcrossSharedEdgesAndDiagonals) {
  SceneBuilder b;
  b.add(rectangleZ(-1, 0, -1, 1, 1));
  b.add(rectangleZ(0, 1, -1, 1, 1));
  b.add({{-1, -1, 3}, {1, -1, 3}, {1, 1, 3}, {-1, 1, 3}});  // its diagonal passes through (0,0,3)
  const RayCaster caster(b.scene());
  for (double y : {-0.5, 0.0, 0.25, 0.999}) {
    EXPECT_TRUE(caster.isOccluded({0, y, 0}, {0, y, 2})) << y;  // exactly on the shared edge
    EXPECT_TRUE(caster.intersect({0, y, 0}, {0, 0, 1}, 0, INFINITY)) << y;
  }
  EXPECT_TRUE(caster.isOccluded({0, 0, 2}, {0, 0, 4}));  // through the internal diagonal
  EXPECT_TRUE(caster.isOccluded({0.5, 0.5, 2}, {0.5, 0.5, 4}));
  EXPECT_TRUE(caster.isOccluded({-0.25, -0.25, 2}, {-0.25, -0.25, 4}));
}

TEST(RayCaster, FarFromTheOriginKeepsSceneRelativePrecision) {
  const Vec3 shift{1e6, -2e6, 3e5};
  SceneBuilder b;
  const PolygonId lower = b.add(rectangleZ(-1, 1, -1, 1, 1, shift));
  const PolygonId upper = b.add(rectangleZ(-1, 1, -1, 1, 1.001, shift));
  const RayCaster caster(b.scene());
  // In absolute float coordinates (ulp 0.125 at 2e6) the two squares would be indistinguishable.
  const auto hit = caster.intersect(Vec3{0.3, 0.2, 0} + shift, {0, 0, 1}, 0, INFINITY);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->polygon, lower);
  EXPECT_NEAR(hit->t, 1.0, 1e-9);
  const auto down = caster.intersect(Vec3{0.3, 0.2, 3} + shift, {0, 0, -1}, 0, INFINITY);
  ASSERT_TRUE(down);
  EXPECT_EQ(down->polygon, upper);
  EXPECT_NEAR(down->t, 3 - 1.001, 1e-9);
  EXPECT_TRUE(caster.isOccluded(Vec3{0, 0, 0} + shift, Vec3{0, 0, 1.0005} + shift));
  EXPECT_FALSE(caster.isOccluded(Vec3{0, 0, 0} + shift, Vec3{0, 0, 0.999} + shift));
}

TEST(RayCaster, EmptySceneNeverHits) {
  const RayCaster caster(PosedScene{});
  EXPECT_FALSE(caster.intersect({0, 0, 0}, {1, 0, 0}, 0, INFINITY));
  EXPECT_FALSE(caster.isOccluded({0, 0, 0}, {1, 0, 0}));
  EXPECT_EQ(caster.triangleCount(), 0);
}

// Random axis-aligned rectangles at distinct heights against a brute-force double-precision
// search; rays passing within 1e-6 of any rectangle's boundary are skipped (float may go either
// way there).
TEST(RayCaster, AgreesWithBruteForceOnRandomScenes) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0, 1);
  SceneBuilder b;
  struct Rect {
    double x0, x1, y0, y1, z;
  };
  std::vector<Rect> rects;
  for (int i = 0; i < 60; ++i) {
    const double x = 10 * unit(rng), y = 10 * unit(rng);
    rects.push_back({x, x + 0.2 + 2 * unit(rng), y, y + 0.2 + 2 * unit(rng), 0.1 + 0.15 * i});
    b.add(rectangleZ(rects.back().x0, rects.back().x1, rects.back().y0, rects.back().y1,
                     rects.back().z));
  }
  const RayCaster caster(b.scene());
  int compared = 0, hits = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 origin{12 * unit(rng) - 1, 12 * unit(rng) - 1, -1};
    const Vec3 target{12 * unit(rng) - 1, 12 * unit(rng) - 1, 10};
    const Vec3 d = target - origin;
    int expected = -1;
    double expectedT = INFINITY;
    bool ambiguous = false;
    for (int k = 0; k < int(rects.size()); ++k) {
      const Rect& r = rects[k];
      const double t = (r.z - origin.z) / d.z;
      const Vec3 p = origin + d * t;
      const double margin =
          std::min({p.x - r.x0, r.x1 - p.x, p.y - r.y0, r.y1 - p.y});  // > 0 inside
      if (std::abs(margin) < 1e-6) ambiguous = true;
      if (margin > 0 && t < expectedT) expected = k, expectedT = t;
    }
    if (ambiguous) continue;
    ++compared;
    const auto hit = caster.intersect(origin, d, 0, 1);
    ASSERT_EQ(hit.has_value(), expected >= 0) << i;
    EXPECT_EQ(caster.isOccluded(origin, target), expected >= 0) << i;
    if (!hit) continue;
    ++hits;
    EXPECT_EQ(hit->polygon, expected) << i;
    EXPECT_NEAR(hit->t, expectedT, 1e-12) << i;
  }
  EXPECT_GT(compared, 2900);
  EXPECT_GT(hits, 1000);
}

TEST(RayCaster, ConcurrentQueriesMatchSerialOnes) {
  SceneBuilder b;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int i = 0; i < 200; ++i) {
    const Vec3 c{10 * unit(rng), 10 * unit(rng), 10 * unit(rng)};
    b.add({c, c + Vec3{unit(rng), unit(rng), unit(rng)}, c + Vec3{unit(rng), -unit(rng), 0.5}});
  }
  const RayCaster caster(b.scene());
  std::vector<std::pair<Vec3, Vec3>> queries;
  for (int i = 0; i < 20000; ++i)
    queries.push_back({Vec3{10 * unit(rng), 10 * unit(rng), 10 * unit(rng)},
                       Vec3{10 * unit(rng), 10 * unit(rng), 10 * unit(rng)}});
  auto answer = [&](int i) {
    const auto hit = caster.intersect(queries[i].first, queries[i].second - queries[i].first, 0, 1);
    return (hit ? hit->polygon : -1) * 2 +
           int(caster.isOccluded(queries[i].first, queries[i].second));
  };
  std::vector<int> serial(queries.size()), parallel(queries.size());
  for (int i = 0; i < int(queries.size()); ++i) serial[i] = answer(i);
  std::vector<std::thread> threads;
  const int kThreads = 8;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      for (int i = t; i < int(queries.size()); i += kThreads) parallel[i] = answer(i);
    });
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(serial, parallel);
}

}  // namespace
}  // namespace penumbra
