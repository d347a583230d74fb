// `penumbra probe SCENE --points FILE`: direct irradiance at given points (DESIGN.md §6).

#include <cstdio>

#include "commands.h"
#include "frame_range.h"
#include "frame_walk.h"
#include "penumbra/base/input_error.h"
#include "penumbra/base/parallel_for.h"
#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/lighting/monte_carlo_estimator.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/receiver_locator.h"
#include "points_file.h"
#include "progress.h"

namespace penumbra::cli {

namespace {

struct ProbeResult {
  Rgb value;
  Rgb standardError;
};

void printCsv(const std::vector<ProbePoint>& points, const std::vector<ProbeResult>& results,
              bool withError) {
  std::printf("x,y,z,nx,ny,nz,r,g,b%s\n", withError ? ",r_stderr,g_stderr,b_stderr" : "");
  for (size_t i = 0; i < points.size(); ++i) {
    const ProbePoint& p = points[i];
    const Rgb& v = results[i].value;
    std::printf("%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", p.position.x, p.position.y,
                p.position.z, p.rawNormal.x, p.rawNormal.y, p.rawNormal.z, v.r, v.g, v.b);
    if (withError) {
      const Rgb& e = results[i].standardError;
      std::printf(",%.17g,%.17g,%.17g", e.r, e.g, e.b);
    }
    std::printf("\n");
  }
}

}  // namespace

int runProbe(const ProbeOptions& options, const CommonOptions& common) {
  if (options.method != "reference" && options.method != "montecarlo" &&
      options.method != "radiosity" && options.method != "dm")
    throw UsageError("--method " + options.method +
                     " is not available in this build (available: reference, dm, montecarlo, "
                     "radiosity)");
  const Scene scene = loadScene(options.scene);
  checkFrame(options.frame, scene.frames);
  const std::vector<ProbePoint> points = readPointsFile(options.points);
  std::vector<ProbeResult> results(points.size());

  // Frame K is frame 0 updated through 1..K (the shared grid and ray caster move with the scene,
  // and the engines take each change through update()), unless --full builds K from scratch.
  DynamicScene live(scene, options.full ? options.frame : 0);
  const auto lieOnNoReceiver = [&](const ProbePoint& p) {
    return InputError(options.points + ":" + std::to_string(p.line),
                      "the point lies on no receiver facing its normal");
  };

  if (options.method == "reference") {
    walkToFrame(live, options.frame, [](const SceneChange&) {});
    const PosedScene& posed = live.posed();
    const ExactReference reference(posed, &live.grid());
    Progress progress("probe (reference)", (long long)points.size(), common.quiet);
    parallelFor((long long)points.size(), common.threads, [&](long long i) {
      const auto receiver =
          locateReceiver(posed, live.grid(), points[i].position, points[i].normal);
      results[i].value =
          reference.irradiance(points[i].position, points[i].normal,
                               receiver ? std::optional(receiver->polygon) : std::nullopt);
      progress.advance();
    });
  } else if (options.method == "dm") {
    // The located face's backprojection gives each value.
    DiscontinuityMeshEngine engine;
    engine.build(live);
    walkToFrame(live, options.frame,
                [&](const SceneChange& change) { engine.update(live, change); });
    Progress progress("probe (dm)", (long long)points.size(), common.quiet);
    for (size_t i = 0; i < points.size(); ++i) {
      const auto value = engine.irradiance(points[i].position, points[i].normal);
      if (!value) throw lieOnNoReceiver(points[i]);
      results[i].value = *value;
      progress.advance();
    }
  } else if (options.method == "radiosity") {
    // Total irradiance (direct + indirect) interpolated on the solution's leaf elements.
    RadiositySolver solver(options.radiosity);
    solver.build(live);
    walkToFrame(live, options.frame,
                [&](const SceneChange& change) { solver.update(live, change); });
    for (size_t i = 0; i < points.size(); ++i) {
      const auto sample = solver.sample(points[i].position, points[i].normal);
      if (!sample) throw lieOnNoReceiver(points[i]);
      results[i].value = sample->total();
    }
  } else {
    walkToFrame(live, options.frame, [](const SceneChange&) {});
    const MonteCarloEstimator estimator(live.posed(), live.rays());
    Progress progress("probe (Monte Carlo)", (long long)points.size(), common.quiet);
    parallelFor((long long)points.size(), common.threads, [&](long long i) {
      const MonteCarloEstimate e =
          estimator.irradiance(points[i].position, points[i].normal, options.monteCarlo);
      results[i] = {e.mean, e.standardError};
      progress.advance();
    });
  }
  printCsv(points, results, options.withError);
  return kOk;
}

}  // namespace penumbra::cli
