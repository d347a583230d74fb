// `penumbra probe SCENE --points FILE`: direct irradiance at given points (DESIGN.md §6).

#include <cstdio>

#include "commands.h"
#include "penumbra/base/input_error.h"
#include "penumbra/base/parallel_for.h"
#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/lighting/monte_carlo_estimator.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/receiver_locator.h"
#include "penumbra/spatial/uniform_grid.h"
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
  if (options.frame < 0 || options.frame >= scene.frames)
    throw UsageError("--frame " + std::to_string(options.frame) +
                     " is outside the scene's frames 0.." + std::to_string(scene.frames - 1));
  const std::vector<ProbePoint> points = readPointsFile(options.points);
  const PosedScene posed = poseAt(scene, options.frame);
  std::vector<ProbeResult> results(points.size());

  if (options.method == "reference") {
    const UniformGrid grid(posed);
    const ExactReference reference(posed, &grid);
    Progress progress("probe (reference)", (long long)points.size(), common.quiet);
    parallelFor((long long)points.size(), common.threads, [&](long long i) {
      const auto receiver = locateReceiver(posed, grid, points[i].position, points[i].normal);
      results[i].value =
          reference.irradiance(points[i].position, points[i].normal,
                               receiver ? std::optional(receiver->polygon) : std::nullopt);
      progress.advance();
    });
  } else if (options.method == "dm") {
    // The incremental update is not built yet, so every frame is a full computation (what
    // --full asks for); the located face's backprojection gives each value.
    DiscontinuityMeshEngine engine;
    engine.build(PosedScene(posed));
    Progress progress("probe (dm)", (long long)points.size(), common.quiet);
    for (size_t i = 0; i < points.size(); ++i) {
      const auto value = engine.irradiance(points[i].position, points[i].normal);
      if (!value)
        throw InputError(options.points + ":" + std::to_string(points[i].line),
                         "the point lies on no receiver facing its normal");
      results[i].value = *value;
      progress.advance();
    }
  } else if (options.method == "radiosity") {
    // Total irradiance (direct + indirect) interpolated on the solution's leaf elements.
    RadiosityOptions radiosityOptions;
    radiosityOptions.tolerance = options.tolerance;
    RadiositySolver solver(radiosityOptions);
    solver.build(posed);
    for (size_t i = 0; i < points.size(); ++i) {
      const auto sample = solver.sample(points[i].position, points[i].normal);
      if (!sample)
        throw InputError(options.points + ":" + std::to_string(points[i].line),
                         "the point lies on no receiver facing its normal");
      results[i].value = sample->total();
    }
  } else {
    const RayCaster rays(posed);
    const MonteCarloEstimator estimator(posed, rays);
    const MonteCarloOptions mc{options.samples, options.batches, options.seed};
    Progress progress("probe (Monte Carlo)", (long long)points.size(), common.quiet);
    parallelFor((long long)points.size(), common.threads, [&](long long i) {
      const MonteCarloEstimate e = estimator.irradiance(points[i].position, points[i].normal, mc);
      results[i] = {e.mean, e.standardError};
      progress.advance();
    });
  }
  printCsv(points, results, options.withError);
  return kOk;
}

}  // namespace penumbra::cli
