#include "penumbra/lighting/monte_carlo_estimator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <thread>

namespace penumbra {
namespace {

// Builds PosedScenes directly, the way poseAt() fills them.
class SceneBuilder {
 public:
  SceneBuilder() { scene_.materials.push_back(Material{"white", {0.5, 0.5, 0.5}, {}, false}); }
  PolygonId add(const Polygon3& vertices, Rgb emission = {}) {
    WorldPolygon p;
    p.id = PolygonId(scene_.polygons.size());
    p.material = 0;
    if (!emission.isBlack()) {
      p.material = int(scene_.materials.size());
      scene_.materials.push_back(Material{"lamp", {0, 0, 0}, emission, false});
      p.isLight = true;
      scene_.lights.push_back(p.id);
    }
    p.vertices = vertices;
    p.plane = supportingPlane(vertices);
    p.area = area(vertices);
    p.bounds = boundingBox(vertices);
    scene_.bounds.extend(p.bounds);
    scene_.polygons.push_back(std::move(p));
    indexObjects(scene_);
    return scene_.polygons.back().id;
  }
  const PosedScene& scene() const { return scene_; }

 private:
  PosedScene scene_;
};

// Rectangle [x0,x1] x [y0,y1] at height z facing down (-z) or up (+z).
Polygon3 rectangle(double x0, double x1, double y0, double y1, double z, bool facingDown) {
  Polygon3 up{{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
  if (facingDown) std::reverse(up.begin(), up.end());
  return up;
}

// Form factor from a differential area to a parallel, facing rectangle a x b, the point below one
// corner at distance c (Howell's catalogue, configuration B-3):
// F = 1/(2 pi) [ X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) + Y/sqrt(1+Y^2) atan(X/sqrt(1+Y^2)) ],
// X = a/c, Y = b/c.
double cornerFormFactor(double a, double b, double c) {
  const double x = a / c, y = b / c;
  return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
          y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
         (2 * std::numbers::pi);
}

// Lambert's formula (DESIGN.md §5), an independent closed form for any polygon entirely in front
// of the receiver.
double lambertFormFactor(const Vec3& p, const Vec3& n, const Polygon3& polygon) {
  double sum = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec3 r0 = polygon[i] - p, r1 = polygon[(i + 1) % polygon.size()] - p;
    const Vec3 c = cross(r0, r1);
    const double len = length(c);
    if (len == 0) continue;
    sum += std::atan2(len, dot(r0, r1)) * dot(n, c / len);
  }
  return std::abs(sum) / (2 * std::numbers::pi);
}

void expectWithin(const MonteCarloEstimate& estimate, double expected, double sigmas = 4) {
  EXPECT_GT(estimate.standardError.r, 0);
  EXPECT_NEAR(estimate.mean.r, expected, sigmas * estimate.standardError.r)
      << "SE " << estimate.standardError.r
      << ", z = " << (estimate.mean.r - expected) / estimate.standardError.r;
}

constexpr double kA = 0.5, kB = 0.75, kC = 1.0, kM = 10.0;

TEST(MonteCarloEstimator, UnoccludedParallelRectangleMatchesClosedForm) {
  SceneBuilder b;
  b.add(rectangle(-kA, kA, -kB, kB, kC, true), Rgb{kM, 2 * kM, 3 * kM});
  const RayCaster caster(b.scene());
  const MonteCarloEstimator estimator(b.scene(), caster);
  const double f = 4 * cornerFormFactor(kA, kB, kC);
  // The closed form and Lambert's formula agree (two independent references).
  EXPECT_NEAR(f, lambertFormFactor({0, 0, 0}, {0, 0, 1}, rectangle(-kA, kA, -kB, kB, kC, true)),
              1e-14);
  const MonteCarloEstimate e = estimator.irradiance({0, 0, 0}, {0, 0, 1});
  expectWithin(e, kM * f);
  // Measured 5.7e-4 relative (one standard error is 6.8e-4): the bound is noise, not error.
  EXPECT_NEAR(e.mean.r, kM * f, 1e-3 * kM * f);
  // Channels scale with the exitance exactly (same samples).
  EXPECT_DOUBLE_EQ(e.mean.g, 2 * e.mean.r);
  EXPECT_DOUBLE_EQ(e.mean.b, 3 * e.mean.r);
  EXPECT_EQ(e.rays, 16 * 256);
  std::printf("[ info     ] parallel rectangle: exact %.10f, MC %.10f +- %.2e (z = %.2f)\n", kM * f,
              e.mean.r, e.standardError.r, (e.mean.r - kM * f) / e.standardError.r);
}

TEST(MonteCarloEstimator, StandardErrorShrinksAtLeastAsOneOverSqrtN) {
  SceneBuilder b;
  b.add(rectangle(-kA, kA, -kB, kB, kC, true), Rgb::gray(kM));
  b.add(rectangle(-10, 0, -10, 10, kC / 2, false));  // blocks half: a discontinuous integrand
  const RayCaster caster(b.scene());
  const MonteCarloEstimator estimator(b.scene(), caster);
  for (const Vec3& p : {Vec3{0.3, 0.1, 0}, Vec3{0, 0, 0}}) {
    MonteCarloOptions coarse, fine;
    coarse.samplesPerLightPerBatch = 16;
    fine.samplesPerLightPerBatch = 16 * 16;
    const double seCoarse = estimator.irradiance(p, {0, 0, 1}, coarse).standardError.r;
    const double seFine = estimator.irradiance(p, {0, 0, 1}, fine).standardError.r;
    std::printf("[ info     ] SE at N=16: %.3e, N=256: %.3e, ratio %.3f (1/sqrt(16) = 0.25)\n",
                seCoarse, seFine, seFine / seCoarse);
    EXPECT_GT(seFine, 0);
    // 16x the samples: 1/sqrt(N) gives 0.25; stratification does better (measured 0.065 and
    // 0.143). Slack for the noise of a 16-batch SE estimate.
    EXPECT_LT(seFine / seCoarse, 0.25 * 1.5);
  }
}

TEST(MonteCarloEstimator, StandardErrorIsCalibrated) {
  // Over many seeds the exact value lies within 2 SE about as often as a t(15) variable does
  // (93.6%), so the SE is neither optimistic nor useless.
  SceneBuilder b;
  b.add(rectangle(-kA, kA, -kB, kB, kC, true), Rgb::gray(kM));
  b.add(rectangle(-10, 0, -10, 10, kC / 2, false));
  const RayCaster caster(b.scene());
  const MonteCarloEstimator estimator(b.scene(), caster);
  const double exact = kM * 4 * cornerFormFactor(kA, kB, kC) / 2;
  int within = 0;
  const int kTrials = 200;
  for (int seed = 1; seed <= kTrials; ++seed) {
    MonteCarloOptions options;
    options.samplesPerLightPerBatch = 9;
    options.seed = std::uint64_t(seed);
    const MonteCarloEstimate e = estimator.irradiance({0, 0, 0}, {0, 0, 1}, options);
    if (std::abs(e.mean.r - exact) <= 2 * e.standardError.r) ++within;
  }
  // Measured 191 of 200. Statistical bounds, not an error's: the count is binomial with
  // p = 0.936 (sd 3.5), so 170 and 198 lie 5 and 3 sd from its mean.
  std::printf("[ info     ] within 2 SE: %d of %d\n", within, kTrials);
  EXPECT_GE(within, int(0.85 * kTrials));
  EXPECT_LE(within, int(0.99 * kTrials));
}

TEST(MonteCarloEstimator, LargeOccluderGivesExactlyZero) {
  SceneBuilder b;
  b.add(rectangle(-kA, kA, -kB, kB, kC, true), Rgb::gray(kM));
  b.add(rectangle(-5, 5, -5, 5, kC / 2, false));
  const RayCaster caster(b.scene());
  const MonteCarloEstimate e =
      MonteCarloEstimator(b.scene(), caster).irradiance({0, 0, 0}, {0, 0, 1});
  EXPECT_EQ(e.mean, Rgb{});
  EXPECT_EQ(e.standardError, Rgb{});
  EXPECT_EQ(e.rays, 16 * 256);
}

TEST(MonteCarloEstimator, OnlyTheFrontSideOfTheLightAndOfTheReceiverCount) {
  SceneBuilder b;
  b.add(rectangle(-kA, kA, -kB, kB, kC, /*facingDown=*/false), Rgb::gray(kM));  // faces away
  const RayCaster caster(b.scene());
  const MonteCarloEstimator estimator(b.scene(), caster);
  const MonteCarloEstimate away = estimator.irradiance({0, 0, 0}, {0, 0, 1});
  EXPECT_EQ(away.mean, Rgb{});
  EXPECT_EQ(away.standardError, Rgb{});
  EXPECT_EQ(away.rays, 0);
  // From above the same light is lit, as a light facing the point; a receiver facing away is not.
  const double f = 4 * cornerFormFactor(kA, kB, kC);
  expectWithin(estimator.irradiance({0, 0, 2 * kC}, {0, 0, -1}), kM * f);
  const MonteCarloEstimate behind = estimator.irradiance({0, 0, 2 * kC}, {0, 0, 1});
  EXPECT_EQ(behind.mean, Rgb{});
  EXPECT_EQ(behind.rays, 0);
}

TEST(MonteCarloEstimator, HalfBlockedLightGivesHalf) {
  // The occluder's edge lies in the plane x = 0 through the point and the light's centre line.
  SceneBuilder b;
  b.add(rectangle(-kA, kA, -kB, kB, kC, true), Rgb::gray(kM));
  b.add(rectangle(-10, 0, -10, 10, kC / 2, false));
  const RayCaster caster(b.scene());
  const MonteCarloEstimate e =
      MonteCarloEstimator(b.scene(), caster).irradiance({0, 0, 0}, {0, 0, 1});
  const double half = kM * 4 * cornerFormFactor(kA, kB, kC) / 2;
  expectWithin(e, half);
  // Measured 2.6e-3 relative, about half a standard error (4.5e-3): the bound is noise.
  EXPECT_NEAR(e.mean.r, half, 0.01 * half);
  std::printf("[ info     ] half blocked: exact %.8f, MC %.8f +- %.2e\n", half, e.mean.r,
              e.standardError.r);
}

TEST(MonteCarloEstimator, TiltedReceiverClipsTheLightAtItsHorizon) {
  // cos(theta_p) = max(0, n . w): the part of the light behind the receiver's plane contributes
  // nothing; compare with Lambert's formula on the light clipped to the receiver's half-space.
  SceneBuilder b;
  const Polygon3 light = rectangle(-1, 1, -1, 1, kC, true);
  b.add(light, Rgb::gray(kM));
  const RayCaster caster(b.scene());
  const MonteCarloEstimator estimator(b.scene(), caster);
  const Vec3 p{0.2, -0.1, 0};
  const Vec3 n = normalize(Vec3{1, 0.3, 0.8});
  const double f = lambertFormFactor(p, n, clipByPlane(light, Plane::fromPointNormal(p, n)));
  expectWithin(estimator.irradiance(p, n), kM * f);
  // Unnormalized normals are accepted.
  EXPECT_EQ(estimator.irradiance(p, n).mean, estimator.irradiance(p, n * 3.0).mean);
}

TEST(MonteCarloEstimator, NonConvexLightAgainstLambert) {
  SceneBuilder b;
  Polygon3 l{{0, 0, 1}, {2, 0, 1}, {2, 1, 1}, {1, 1, 1}, {1, 2, 1}, {0, 2, 1}};
  std::reverse(l.begin(), l.end());  // face down
  b.add(l, Rgb::gray(kM));
  const RayCaster caster(b.scene());
  const MonteCarloEstimator estimator(b.scene(), caster);
  for (const Vec3& p : {Vec3{0.5, 0.5, 0}, Vec3{1.5, 1.5, 0.3}, Vec3{-1, 0.5, 0.8}}) {
    const Vec3 n = normalize(Vec3{0.1, 0.2, 1});
    expectWithin(estimator.irradiance(p, n), kM * lambertFormFactor(p, n, l));
  }
}

TEST(MonteCarloEstimator, OtherLightsOccludeButNotThemselves) {
  // A large low light hides a high one completely: only the low light's irradiance arrives.
  SceneBuilder b;
  b.add(rectangle(-kA, kA, -kB, kB, kC, true), Rgb::gray(kM));
  b.add(rectangle(-0.2, 0.2, -0.2, 0.2, 3 * kC, true), Rgb::gray(1000 * kM));
  const RayCaster caster(b.scene());
  const MonteCarloEstimate e =
      MonteCarloEstimator(b.scene(), caster).irradiance({0, 0, 0}, {0, 0, 1});
  expectWithin(e, kM * 4 * cornerFormFactor(kA, kB, kC));
  // Two coplanar lights side by side: each is unoccluded by the other.
  SceneBuilder side;
  side.add(rectangle(-kA, 0, -kB, kB, kC, true), Rgb::gray(kM));
  side.add(rectangle(0, kA, -kB, kB, kC, true), Rgb::gray(kM));
  const RayCaster sideCaster(side.scene());
  expectWithin(MonteCarloEstimator(side.scene(), sideCaster).irradiance({0, 0, 0}, {0, 0, 1}),
               kM * 4 * cornerFormFactor(kA, kB, kC));
}

TEST(MonteCarloEstimator, WallStandingOnTheReceiver) {
  // A floor receiver, a wall standing on it (contact along x = 0.3), a light above that the wall
  // cuts at x = 0.3: points on the floor, even a hair from the contact line, see exactly the part
  // of the light on their side. The floor itself never shadows its own points.
  SceneBuilder b;
  b.add(rectangle(-5, 5, -5, 5, 0, false));
  b.add(rectangle(-kA, kA, -kB, kB, kC, true), Rgb::gray(kM));
  b.add({{0.3, -5, 0}, {0.3, 5, 0}, {0.3, 5, 2}, {0.3, -5, 2}});
  const RayCaster caster(b.scene());
  const MonteCarloEstimator estimator(b.scene(), caster);
  ASSERT_LT(caster.epsilon(), 5e-4);
  const Polygon3 right = rectangle(0.3, kA, -kB, kB, kC, true);
  const Polygon3 left = rectangle(-kA, 0.3, -kB, kB, kC, true);
  for (double x : {0.6, 0.3005}) {
    const Vec3 p{x, 0.1, 0};
    expectWithin(estimator.irradiance(p, {0, 0, 1}), kM * lambertFormFactor(p, {0, 0, 1}, right));
  }
  for (double x : {0.0, 0.2995}) {
    const Vec3 p{x, -0.2, 0};
    expectWithin(estimator.irradiance(p, {0, 0, 1}), kM * lambertFormFactor(p, {0, 0, 1}, left));
  }
}

TEST(MonteCarloEstimator, DeterministicOrderIndependentAndThreadSafe) {
  SceneBuilder b;
  b.add(rectangle(-kA, kA, -kB, kB, kC, true), Rgb::gray(kM));
  b.add(rectangle(-10, 0, -10, 10, kC / 2, false));
  const RayCaster caster(b.scene());
  const MonteCarloEstimator estimator(b.scene(), caster);
  MonteCarloOptions options;
  options.samplesPerLightPerBatch = 32;
  std::vector<Vec3> points;
  for (int i = 0; i < 64; ++i) points.push_back({-0.5 + i / 64.0, 0.1 * std::sin(i), 0});
  std::vector<Rgb> forward, reversed(points.size()), threaded(points.size());
  for (const Vec3& p : points) forward.push_back(estimator.irradiance(p, {0, 0, 1}, options).mean);
  for (int i = int(points.size()) - 1; i >= 0; --i)
    reversed[i] = estimator.irradiance(points[i], {0, 0, 1}, options).mean;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (size_t i = t; i < points.size(); i += 4)
        threaded[i] = estimator.irradiance(points[i], {0, 0, 1}, options).mean;
    });
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(forward, reversed);
  EXPECT_EQ(forward, threaded);
  // A different seed gives a different (but statistically equal) estimate.
  MonteCarloOptions other = options;
  other.seed = 2;
  EXPECT_NE(estimator.irradiance(points[5], {0, 0, 1}, other).mean, forward[5]);
}

TEST(MonteCarloEstimator, OptionsAreValidated) {
  SceneBuilder b;
  b.add(rectangle(-kA, kA, -kB, kB, kC, true), Rgb::gray(kM));
  const RayCaster caster(b.scene());
  const MonteCarloEstimator estimator(b.scene(), caster);
  MonteCarloOptions bad;
  bad.batches = 0;
  EXPECT_THROW(estimator.irradiance({0, 0, 0}, {0, 0, 1}, bad), std::invalid_argument);
  bad = {};
  bad.samplesPerLightPerBatch = 0;
  EXPECT_THROW(estimator.irradiance({0, 0, 0}, {0, 0, 1}, bad), std::invalid_argument);
  MonteCarloOptions single;
  single.batches = 1;
  const MonteCarloEstimate e = estimator.irradiance({0, 0, 0}, {0, 0, 1}, single);
  EXPECT_GT(e.mean.r, 0);
  EXPECT_TRUE(std::isnan(e.standardError.r));
  // More triangles than samples: one sample per triangle each.
  single.samplesPerLightPerBatch = 1;
  EXPECT_EQ(estimator.irradiance({0, 0, 0}, {0, 0, 1}, single).rays, 2);
}

}  // namespace
}  // namespace penumbra
