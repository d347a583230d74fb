#include "penumbra/radiosity/combined_solution.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "penumbra/base/parallel_for.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/lighting/path_traced_reference.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"
#include "support/boxes.h"
#include "support/scene_builder.h"

namespace penumbra {
namespace {

PosedScene cornellBox() {
  return poseAt(
      loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json"), 0);
}

RadiosityOptions withTolerance(double tolerance) {
  RadiosityOptions options;
  options.tolerance = tolerance;
  return options;
}

// The independent path tracer's estimates at the points, `paths` each (sampled direct light: its
// visibility is its own shadow rays, not the exact reference's clipping that the discontinuity
// mesh is checked against); point i's seed is firstSeed + i.
std::vector<PathTracedEstimate> pathTraced(const PosedScene& posed,
                                           const std::vector<ReceiverPoint>& points, int paths,
                                           std::uint64_t firstSeed) {
  const RayCaster rays(posed);
  const PathTracedReference tracer(posed, rays);
  std::vector<PathTracedEstimate> estimates(points.size());
  parallelFor((long long)points.size(), 0, [&](long long i) {
    estimates[i] = tracer.irradiance(points[i].p, points[i].n, points[i].receiver, paths,
                                     firstSeed + std::uint64_t(i));
  });
  return estimates;
}

// The direct part is the discontinuity mesh's, exact: against the exact reference at random
// receiver points and at the adversarial ones, the corners where the short block stands on the
// floor and points a hair from its foot, in its contact shadow.
TEST(CombinedSolution, DirectPartIsTheExactReference) {
  const PosedScene posed = cornellBox();
  const DynamicScene live(posed);
  CombinedSolution solution(withTolerance(1e-2));
  solution.build(live);
  const ExactReference reference(posed, &live.grid());
  std::vector<ReceiverPoint> points = sampleReceiverPoints(posed, 300, 3);
  // The short block's foot (polygon 11 lies on the floor): its corners, and 1e-5 outside them.
  const Vec3 up{0, 1, 0};
  for (const Vec3& corner : posed.polygons[11].vertices) {
    points.push_back({corner, up, 0});
    const Vec3 outward = normalize(corner - Vec3{0.186, 0, 0.1685});
    points.push_back({corner + outward * 1e-5, up, 0});
  }
  int compared = 0;
  for (const ReceiverPoint& p : points) {
    const auto sample = solution.sample(p.p, p.n);
    if (!sample) continue;  // a point on no receiver facing n (the locator's tolerance)
    const Rgb exact = reference.irradiance(p.p, p.n, p.receiver);
    const double scale = std::max(1.0, exact.maxComponent());
    EXPECT_NEAR(sample->direct.r, exact.r, 1e-9 * scale) << p.p.x << " " << p.p.y << " " << p.p.z;
    EXPECT_NEAR(sample->direct.g, exact.g, 1e-9 * scale);
    EXPECT_NEAR(sample->direct.b, exact.b, 1e-9 * scale);
    EXPECT_TRUE(sample->indirect.isFinite());
    EXPECT_GE(std::min({sample->indirect.r, sample->indirect.g, sample->indirect.b}), 0);
    ++compared;
  }
  EXPECT_GE(compared, 300);
}

// Against the independent path tracer at open receiver points (those whose irradiance is above
// 1e-3 of the mean): the combined solution's total irradiance is closer than radiosity's alone,
// its direct part exact and its indirect part gathered at the point. Measured here (session 9):
// 59 points, median 0.98% against 2.97% for radiosity alone, the reference's standard error
// 0.75%; bench/radiosity_error_curve on 149 points and 262,144 paths each: 0.83% against 3.7%.
TEST(CombinedSolution, CloserToPathTracingThanRadiosityAlone) {
  const PosedScene posed = cornellBox();
  const DynamicScene live(posed);
  CombinedSolution combined(withTolerance(1e-3));
  combined.build(live);
  RadiositySolver alone(withTolerance(1e-3));
  alone.build(live);

  const std::vector<ReceiverPoint> points = sampleReceiverPoints(posed, 64, 11);
  std::vector<double> reference, noise;
  for (const PathTracedEstimate& e : pathTraced(posed, points, 32768, 500)) {
    reference.push_back(e.total().average());
    noise.push_back(e.totalStandardError.average());
  }
  double mean = 0;
  for (double r : reference) mean += r / double(reference.size());
  std::vector<double> combinedErrors, aloneErrors, relativeNoise;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!(reference[i] > 1e-3 * mean)) continue;
    const auto c = combined.sample(points[i].p, points[i].n);
    const auto a = alone.sample(points[i].p, points[i].n);
    ASSERT_TRUE(c && a);
    combinedErrors.push_back(std::abs(c->total().average() - reference[i]) / reference[i]);
    aloneErrors.push_back(std::abs(a->total().average() - reference[i]) / reference[i]);
    relativeNoise.push_back(noise[i] / reference[i]);
  }
  const auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::printf(
      "%zu open points: median error combined %.2f%%, radiosity alone %.2f%%; the "
      "reference's standard error %.2f%%\n",
      combinedErrors.size(), 100 * median(combinedErrors), 100 * median(aloneErrors),
      100 * median(relativeNoise));
  ASSERT_GE(combinedErrors.size(), 55u);
  EXPECT_LT(median(combinedErrors), median(aloneErrors));
  EXPECT_LT(median(combinedErrors), 0.02);
}

// Issue 19's bias: the indirect light summed over random open points of the chair room within
// 1% of the path tracer's. A gather ray that meets a surface used to take the mean radiosity of
// the leaf it met, and what a point sees of a surface is more often its lit part (the floor under
// a table hides from the walls as it hides from the lamp): the chair room's indirect light came
// out 1.5% low (bench/radiosity_error_curve, 136 points at 65,536 paths). Rays now take the
// radiosity of the cell they meet. The path tracer's indirect part is its own (sampled direct
// light, shadow rays): nothing of the solution is in it.
TEST(CombinedSolution, IndirectLightIsNotLowInTheChairRoom) {
  const PosedScene posed =
      poseAt(loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/chair-room/chair-room.json"), 0);
  const DynamicScene live(posed);
  CombinedSolution combined(withTolerance(3e-3), {}, 512);
  combined.build(live);
  const std::vector<ReceiverPoint> points = sampleReceiverPoints(posed, 80, 19);
  const std::vector<PathTracedEstimate> reference = pathTraced(posed, points, 8192, 900);
  double mean = 0;
  for (const PathTracedEstimate& r : reference) mean += r.total().average() / double(points.size());
  double solution = 0, traced = 0, tracedVariance = 0;
  int open = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!(reference[i].total().average() > 1e-3 * mean)) continue;
    const auto c = combined.sample(points[i].p, points[i].n);
    ASSERT_TRUE(c);
    solution += c->indirect.average();
    traced += reference[i].indirect.average();
    tracedVariance += std::pow(reference[i].indirectStandardError.average(), 2);
    ++open;
  }
  const double ratio = solution / traced, noise = std::sqrt(tracedVariance) / traced;
  std::printf(
      "%d open points: indirect summed %.4f of the path tracer's (its standard error %.4f)\n", open,
      ratio, noise);
  ASSERT_GE(open, 70);
  EXPECT_LT(noise, 0.003);
  EXPECT_NEAR(ratio, 1, 0.01);
}

// Adversarial points: in the Cornell box's corners, 1-15 mm from where the back wall meets the
// ceiling and the side walls, against the path tracer. There the nearer surface fills half the
// hemisphere, and its strip next to the point sends most: gathered by its form factor with its
// leaves' means, a point 1.4 mm below the ceiling read 24% too much (the strip is darker than
// the leaf: the corner hides the room from it); rays meeting it that close take what the point
// they meet reflects.
TEST(CombinedSolution, CornersAreNotTooBright) {
  const PosedScene posed = cornellBox();
  const DynamicScene live(posed);
  CombinedSolution combined(withTolerance(1e-3));
  combined.build(live);
  // The back wall (z = 0.5592, facing -z) below the ceiling (y = 0.5488) and beside the left
  // wall (x = 0), and the ceiling (facing -y) beside the back wall.
  std::vector<ReceiverPoint> points;
  for (double gap : {0.0014, 0.005, 0.015})
    for (double along : {0.0857, 0.278, 0.47}) {
      points.push_back({{along, 0.5488 - gap, 0.5592}, {0, 0, -1}, 2});
      points.push_back({{gap, along, 0.5592}, {0, 0, -1}, 2});
      points.push_back({{along, 0.5488, 0.5592 - gap}, {0, -1, 0}, 1});
    }
  const std::vector<PathTracedEstimate> reference = pathTraced(posed, points, 32768, 70);
  double worst = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const auto c = combined.sample(points[i].p, points[i].n);
    ASSERT_TRUE(c) << i;
    const double r = reference[i].total().average();
    const double error = (c->total().average() - r) / r;
    const double noise = reference[i].totalStandardError.average() / r;
    EXPECT_LT(std::abs(error), 0.03 + 3 * noise)
        << "at " << points[i].p.x << " " << points[i].p.y << " " << points[i].p.z << ": "
        << c->total().average() << " against " << r << " +- " << 100 * noise << "%";
    worst = std::max(worst, std::abs(error));
  }
  std::printf("%zu corner points: largest error %.2f%%\n", points.size(), 100 * worst);
}

// Points in front of the Cornell box's opening, on the black walls and ceiling of the dark room
// there, see the lit inside through a sliver of their hemisphere. With one round of rays a point
// met it some 50 times in 1,024 and read up to 25% off; rays are now cast until a quarter of them
// met something that sends light. Against the path tracer (its own standard error 2-4% there),
// the rms of the relative errors, less the reference's noise in quadrature.
TEST(CombinedSolution, PointsLitThroughTheOpeningAreNotNoisy) {
  const PosedScene posed = cornellBox();
  const DynamicScene live(posed);
  CombinedSolution combined(withTolerance(1e-3));
  combined.build(live);
  // The black ceiling (polygon 6, y = 0.5488, facing down) and right wall (polygon 8, x = 0.556,
  // facing -x) in front of the opening (z < 0).
  std::vector<ReceiverPoint> points;
  for (double z : {-0.45, -0.6, -0.75})
    for (double t : {0.1, 0.3, 0.5}) {
      points.push_back({{t, 0.5488, z}, {0, -1, 0}, 6});
      points.push_back({{0.556, t, z}, {-1, 0, 0}, 8});
    }
  const std::vector<PathTracedEstimate> reference = pathTraced(posed, points, 65536, 40);
  double squares = 0, noiseSquares = 0, worst = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const auto c = combined.sample(points[i].p, points[i].n);
    ASSERT_TRUE(c) << i;
    const double r = reference[i].total().average();
    ASSERT_GT(r, 0) << i;
    const double error = (c->total().average() - r) / r;
    squares += error * error;
    noiseSquares += std::pow(reference[i].totalStandardError.average() / r, 2);
    worst = std::max(worst, std::abs(error));
  }
  const double rms = std::sqrt(squares / double(points.size()));
  const double noise = std::sqrt(noiseSquares / double(points.size()));
  const double beyondNoise = std::sqrt(std::max(0.0, rms * rms - noise * noise));
  std::printf(
      "%zu points: rms error %.2f%% (the reference's noise %.2f%%), beyond it %.2f%%, "
      "largest %.2f%%\n",
      points.size(), 100 * rms, 100 * noise, 100 * beyondNoise, 100 * worst);
  EXPECT_LT(beyondNoise, 0.05);
}

// Issue 19's gaps: crates 2, 5 and 10 mm from the walls under a lamp. A gap is far narrower than
// an element, so a gather ray from a point in it meets, millimetres away, a leaf whose radiosity
// is its mean over all of it, most of it outside the gap in the light: with those means the wall
// behind the 5 mm gap read 0.164 where the path tracer gives 0.0004, the crate's back 0.123 and
// the floor in the gap 0.068 against 0.006. Rays that meet a leaf closer than its size are now
// continued there with its exact direct light (RadiositySolver::reflectedAlong). Issue 19 asks
// for points in contact shadows and gaps within 5% or 0.01 of the scene's mean irradiance of the
// path tracer.
TEST(CombinedSolution, NoLightThroughNarrowGaps) {
  test::SceneBuilder builder;
  builder.addMaterial("white", Rgb{0.7, 0.7, 0.7})
      .addMaterial("lamp", Rgb::gray(0), Rgb{100, 100, 100});
  test::addRoom(builder, "white", {0, 0, 0}, {4, 3, 5});
  const auto lamp = test::boxFaces({1.7, 2.97, 2.2}, {2.3, 2.99, 2.8});
  for (size_t i = 0; i < lamp.size(); ++i)
    builder.addPolygon(i == 2 ? "lamp" : "white", lamp[i], "lamp");
  test::addBox(builder, "white", "crate-5mm", {1.0, 0, 0.005}, {1.6, 0.6, 0.605});
  test::addBox(builder, "white", "crate-2mm", {0.002, 0, 2.0}, {0.602, 0.6, 2.6});
  test::addBox(builder, "white", "crate-10mm", {3.39, 0, 3.0}, {3.99, 0.6, 3.6});
  const PosedScene posed = builder.pose();
  const DynamicScene live(posed);
  CombinedSolution combined(withTolerance(1e-3));
  combined.build(live);
  const RayCaster rays(posed);
  const PathTracedReference tracer(posed, rays);

  // The scene's mean irradiance: the path tracer's mean at points uniform over the receivers.
  const std::vector<ReceiverPoint> uniform = sampleReceiverPoints(posed, 64, 3);
  std::vector<double> values(uniform.size());
  parallelFor((long long)uniform.size(), 0, [&](long long i) {
    values[size_t(i)] =
        tracer.irradiance(uniform[i].p, uniform[i].n, uniform[i].receiver, 2048, 700 + i)
            .total()
            .average();
  });
  double mean = 0;
  for (double v : values) mean += v / double(values.size());

  struct Probe {
    const char* where;
    Vec3 p, n;
    bool inGap;  // else in the open: within 2% (measured 0.5%)
  };
  const std::vector<Probe> probes{
      {"wall behind the 5 mm gap", {1.3, 0.3, 0}, {0, 0, 1}, true},
      {"crate's back, 5 mm gap", {1.3, 0.3, 0.005}, {0, 0, -1}, true},
      {"floor in the 5 mm gap", {1.3, 0, 0.0025}, {0, 1, 0}, true},
      {"floor 2 mm before the crate", {1.3, 0, 0.607}, {0, 1, 0}, true},
      {"wall behind the 2 mm gap", {0, 0.3, 2.3}, {1, 0, 0}, true},
      {"crate's back, 2 mm gap", {0.002, 0.3, 2.3}, {-1, 0, 0}, true},
      {"wall behind the 10 mm gap", {4, 0.3, 3.3}, {-1, 0, 0}, true},
      {"floor in the 10 mm gap", {3.995, 0, 3.3}, {0, 1, 0}, true},
      {"wall above the 5 mm crate", {1.3, 0.8, 0}, {0, 0, 1}, false},
      {"floor in the open", {2.5, 0, 2.5}, {0, 1, 0}, false},
  };
  std::vector<PathTracedEstimate> traced(probes.size());
  std::vector<PolygonId> receivers(probes.size(), -1);
  for (size_t i = 0; i < probes.size(); ++i)
    for (const WorldPolygon& w : posed.polygons)
      if (dot(w.plane.normal, probes[i].n) > 1 - 1e-12 &&
          std::abs(w.plane.signedDistance(probes[i].p)) < 1e-12 &&
          w.bounds.expanded(1e-12).contains(probes[i].p))
        receivers[i] = w.id;
  parallelFor((long long)probes.size(), 0, [&](long long i) {
    if (receivers[i] >= 0)
      traced[i] = tracer.irradiance(probes[i].p, probes[i].n, receivers[i], 65536, 900 + i);
  });
  std::printf("scene mean irradiance %.4f (path tracer, 64 points)\n", mean);
  for (size_t i = 0; i < probes.size(); ++i) {
    const Probe& q = probes[i];
    ASSERT_GE(receivers[i], 0) << q.where;
    const auto c = combined.sample(q.p, q.n);
    ASSERT_TRUE(c) << q.where;
    const double got = c->total().average(), expected = traced[i].total().average();
    const double noise = 3 * traced[i].totalStandardError.average();
    std::printf("  %-28s combined %.5f (direct %.5f), path tracer %.5f +- %.5f\n", q.where, got,
                c->direct.average(), expected, noise / 3);
    const double allowed = q.inGap ? std::max(0.05 * expected, 0.01 * mean) : 0.02 * expected;
    EXPECT_LE(std::abs(got - expected), allowed + noise) << q.where;
  }
}

}  // namespace
}  // namespace penumbra
