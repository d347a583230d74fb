// Cost of the exact reference irradiance per point against scene size (with and without the
// grid's occluder culling), and the Monte Carlo estimator's error against its sample count at the
// same points — measured side by side in one run, on one thread.
//
// Usage: reference_bench [--points N] [--quick]

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "bench_main.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/lighting/monte_carlo_estimator.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_generator.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"
#include "penumbra_points.h"

using namespace penumbra;

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

static int benchMain(int argc, char** argv) {
  int pointCount = 400;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--points") && i + 1 < argc) pointCount = std::atoi(argv[++i]);
    if (!std::strcmp(argv[i], "--quick")) quick = true;
  }
  const std::string root = PENUMBRA_SOURCE_DIR;
  std::vector<std::pair<std::string, std::string>> scenes = {
      {"desk-145", root + "/scenes/office-desk/desk-145.json"},
      {"desk-307", root + "/scenes/office-desk/desk-307.json"},
      {"desk-475", root + "/scenes/office-desk/desk-475.json"},
      {"furnished-room-1300", root + "/scenes/chair-room/furnished-room.json"}};
  const auto tmp = std::filesystem::temp_directory_path() / "penumbra-bench";
  std::filesystem::create_directories(tmp);
  for (int n : quick ? std::vector<int>{1000} : std::vector<int>{1000, 10000, 100000}) {
    const auto path = tmp / ("generated-" + std::to_string(n) + ".json");
    std::ofstream(path) << generateSceneJson({n, 1, 4});
    scenes.push_back({"generated-" + std::to_string(n), path.string()});
  }

  std::printf("# Exact reference: cost per point (one thread, %d random receiver points)\n",
              pointCount);
  std::printf("%-22s %9s %7s %12s %12s %10s %12s\n", "scene", "polygons", "lights", "grid us/pt",
              "brute us/pt", "speed-up", "grid build s");
  for (const auto& [name, path] : scenes) {
    const Scene scene = loadScene(path);
    const PosedScene posed = poseAt(scene, 0);
    const auto points = sampleReceiverPoints(posed, pointCount, 7);
    auto start = Clock::now();
    const UniformGrid grid(posed);
    const double gridBuild = secondsSince(start);
    const ExactReference withGrid(posed, &grid), bruteForce(posed);
    double checksum = 0;
    start = Clock::now();
    for (const auto& q : points) checksum += withGrid.irradiance(q.p, q.n, q.receiver).r;
    const double gridSeconds = secondsSince(start);
    double bruteSeconds = 0;
    const bool runBrute = true;
    if (runBrute) {
      double check2 = 0;
      start = Clock::now();
      for (const auto& q : points) check2 += bruteForce.irradiance(q.p, q.n, q.receiver).r;
      bruteSeconds = secondsSince(start);
      if (check2 != checksum)
        std::printf("  (grid and brute force differ: %.17g vs %.17g)\n", checksum, check2);
    }
    std::printf(
        "%-22s %9zu %7zu %12.1f %12s %10s %12.3f\n", name.c_str(), posed.polygons.size(),
        posed.lights.size(), 1e6 * gridSeconds / pointCount,
        runBrute ? std::to_string(int(1e6 * bruteSeconds / pointCount)).c_str() : "-",
        runBrute ? (std::to_string(bruteSeconds / gridSeconds).substr(0, 5) + "x").c_str() : "-",
        gridBuild);
  }

  // Monte Carlo error against samples, at penumbra points of desk-475 (where 0 < E < unoccluded).
  std::printf("\n# Monte Carlo vs exact at penumbra points of desk-475 (16 batches)\n");
  const Scene desk = loadScene(root + "/scenes/office-desk/desk-475.json");
  const PosedScene posed = poseAt(desk, 0);
  const UniformGrid grid(posed);
  const ExactReference reference(posed, &grid);
  const RayCaster rays(posed);
  const MonteCarloEstimator monteCarlo(posed, rays);
  const std::vector<bench::PenumbraPoint> penumbra =
      bench::samplePenumbraPoints(posed, reference, 200, 11);
  auto start = Clock::now();
  for (const auto& [q, value] : penumbra) (void)reference.irradiance(q.p, q.n, q.receiver);
  const double exactSeconds = secondsSince(start) / penumbra.size();
  std::printf("penumbra points: %zu; exact reference: %.1f us/point\n", penumbra.size(),
              1e6 * exactSeconds);
  std::printf("%12s %14s %14s %12s %16s\n", "rays/point", "rms rel error", "mean rel SE",
              "us/point", "MC/exact time");
  for (int samples : quick ? std::vector<int>{4, 64} : std::vector<int>{4, 16, 64, 256, 1024}) {
    const MonteCarloOptions options{samples, 16, 3};
    double sumSq = 0, sumSe = 0;
    long long rayCount = 0;
    start = Clock::now();
    for (size_t i = 0; i < penumbra.size(); ++i) {
      const auto& [q, exact] = penumbra[i];
      const MonteCarloEstimate e = monteCarlo.irradiance(q.p, q.n, options);
      const double rel = (e.mean.r - exact) / exact;
      sumSq += rel * rel;
      sumSe += e.standardError.r / exact;
      rayCount += e.rays;
    }
    const double seconds = secondsSince(start) / penumbra.size();
    std::printf("%12lld %14.2e %14.2e %12.1f %15.1fx\n", rayCount / (long long)penumbra.size(),
                std::sqrt(sumSq / penumbra.size()), sumSe / penumbra.size(), 1e6 * seconds,
                seconds / exactSeconds);
  }
  return 0;
}

int main(int argc, char** argv) {
  return penumbra::bench::runReportingErrors("reference_bench", argc, argv, benchMain);
}
