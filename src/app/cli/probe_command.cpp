// `penumbra probe SCENE --points FILE`: direct irradiance at given points (DESIGN.md §6).

#include <chrono>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "frame_range.h"
#include "frame_walk.h"
#include "penumbra/base/input_error.h"
#include "penumbra/base/parallel_for.h"
#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/lighting/monte_carlo_estimator.h"
#include "penumbra/radiosity/combined_solution.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/receiver_locator.h"
#include "points_file.h"
#include "progress.h"
#include "report_file.h"

namespace penumbra::cli {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

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
      options.method != "radiosity" && options.method != "galerkin" && options.method != "dm" &&
      options.method != "combined")
    throw UsageError("--method " + options.method +
                     " is not available in this build (available: reference, dm, montecarlo, "
                     "radiosity, galerkin, combined)");
  const Scene scene = loadScene(options.scene);
  checkFrame(options.frame, scene.frames);
  const std::vector<ProbePoint> points = readPointsFile(options.points);
  std::vector<ProbeResult> results(points.size());
  const auto start = std::chrono::steady_clock::now();
  nlohmann::json report;

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
    std::map<DiscontinuityMeshEngine::Answer, long long> answers;
    for (size_t i = 0; i < points.size(); ++i) {
      const auto answered = engine.query(points[i].position, points[i].normal);
      if (!answered) throw lieOnNoReceiver(points[i]);
      results[i].value = answered->irradiance;
      ++answers[answered->answer];
      progress.advance();
    }
    using Answer = DiscontinuityMeshEngine::Answer;
    const long long byMesh = answers[Answer::kMesh];
    report["answered_by_mesh"] = byMesh;
    report["answered_at_point"] = (long long)points.size() - byMesh;
    report["at_point"] = {{"outside_faces", answers[Answer::kOutsideFaces]},
                          {"unresolved_face", answers[Answer::kUnresolvedFace]},
                          {"sliver_face", answers[Answer::kSliverFace]},
                          {"near_eee_polyline", answers[Answer::kNearEeePolyline]},
                          {"degenerate", answers[Answer::kDegenerate]},
                          {"unlabelled", answers[Answer::kUnlabelled]},
                          {"on_another_polygon", answers[Answer::kOnAnotherPolygon]}};
  } else if (options.method == "radiosity") {
    // Total irradiance (direct + indirect) interpolated on the solution's leaf elements.
    RadiositySolver solver(withThreads(options.radiosity, common));
    solver.build(live);
    walkToFrame(live, options.frame,
                [&](const SceneChange& change) { solver.update(live, change); });
    for (size_t i = 0; i < points.size(); ++i) {
      const auto sample = solver.sample(points[i].position, points[i].normal);
      if (!sample) throw lieOnNoReceiver(points[i]);
      results[i].value = sample->total();
    }
  } else if (options.method == "galerkin") {
    // Total irradiance from the Galerkin core: the linear functions of the leaf holding the
    // point; frame K reached by line-space updates from frame 0 unless --full.
    GalerkinRadiosity solver(galerkinOptions(options.radiosity, common));
    solver.build(live);
    walkToFrame(live, options.frame,
                [&](const SceneChange& change) { solver.update(live, change); });
    for (size_t i = 0; i < points.size(); ++i) {
      const auto sample = solver.sample(points[i].position, points[i].normal);
      if (!sample) throw lieOnNoReceiver(points[i]);
      results[i].value = sample->total();
    }
  } else if (options.method == "combined") {
    // Total irradiance: exact direct from the discontinuity mesh, radiosity's indirect (lit by
    // that exact direct light) interpolated on its leaves.
    CombinedSolution solution(withThreads(options.radiosity, common));
    solution.build(live);
    walkToFrame(live, options.frame,
                [&](const SceneChange& change) { solution.update(live, change); });
    for (size_t i = 0; i < points.size(); ++i) {
      const auto sample = solution.sample(points[i].position, points[i].normal);
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
  if (!options.report.empty()) {
    report["method"] = options.method;
    report["points"] = points.size();
    report["full"] = options.full;
    const nlohmann::json frame = {{"frame", options.frame}, {"seconds", secondsSince(start)}};
    writeReport(report, options.report, options.scene, scene.polygonCount(),
                nlohmann::json::array({frame}));
  }
  return kOk;
}

}  // namespace penumbra::cli
