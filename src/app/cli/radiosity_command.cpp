// `penumbra radiosity SCENE [--frames A:B] --update full [--solver hierarchical|galerkin]
// [--tolerance T] --report R.json`: the radiosity solution over a range of frames, with per-frame
// statistics.

#include <cstdio>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "frame_range.h"
#include "frame_walk.h"
#include "penumbra/radiosity/galerkin/galerkin_radiosity.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "progress.h"
#include "report_file.h"

namespace penumbra::cli {

namespace {

nlohmann::json statsJson(const RadiosityStats& s) {
  return {{"links", s.links},
          {"active_links", s.activeLinks},
          {"passive_links", s.passiveLinks},
          {"elements", s.elements},
          {"leaves", s.leaves},
          {"clusters", s.clusters},
          {"shafts", s.shafts},
          {"polygon_shafts", s.polygonShafts},
          {"visibility_rays", s.visibilityRays},
          {"iterations", s.iterations},
          {"residual", s.residual},
          {"refine_seconds", s.refineSeconds},
          {"solve_seconds", s.solveSeconds},
          {"final_gather_seconds", s.finalGatherSeconds},
          {"final_gather_rays", s.finalGatherRays},
          {"final_gather_misses", s.finalGatherMisses},
          {"final_iterations", s.finalIterations},
          {"exact_visibility_points", s.exactVisibilityPoints},
          {"memory_bytes",
           {{"clusters", s.clusterBytes},
            {"elements", s.elementBytes},
            {"active_links", s.activeLinkBytes},
            {"passive_links", s.passiveLinkBytes},
            {"shafts", s.shaftBytes},
            {"mesh", s.meshBytes},
            {"total", s.totalBytes()}}}};
}

nlohmann::json statsJson(const GalerkinStats& s) {
  return {{"links", s.activeLinks + s.passiveLinks},
          {"active_links", s.activeLinks},
          {"passive_links", s.passiveLinks},
          {"elements", s.elements},
          {"leaves", s.leaves},
          {"clusters", s.clusters},
          {"point_pairs", s.pointPairs},
          {"visibility_rays", s.visibilityRays},
          {"unoccluded_links", s.unoccludedLinks},
          {"iterations", s.iterations},
          {"refine_seconds", s.refineSeconds},
          {"solve_seconds", s.solveSeconds},
          {"memory_bytes",
           {{"clusters", s.clusterBytes},
            {"elements", s.elementBytes},
            {"links", s.linkBytes},
            {"total", s.totalBytes()}}}};
}

// The Galerkin core over the frames (it recomputes each frame inside update()).
int runGalerkin(const RadiosityCommandOptions& options, const CommonOptions& common,
                const Scene& scene, const FrameRange& range) {
  DynamicScene live(scene, range.first);
  GalerkinRadiosity solver(galerkinOptions(options.radiosity, common));
  nlohmann::json frames = nlohmann::json::array();
  Progress progress("radiosity (galerkin)", range.last - range.first + 1, common.quiet);
  for (int frame = range.first; frame <= range.last; ++frame) {
    const int moved = buildOrStep(live, solver, frame, frame == range.first);
    const GalerkinStats& s = solver.stats();
    nlohmann::json entry = statsJson(s);
    entry["frame"] = frame;
    entry["seconds"] = s.totalSeconds;
    entry["moved_objects"] = moved;
    frames.push_back(entry);
    if (!common.quiet)
      std::fprintf(stderr, "frame %d: %.3f s, %lld links, %lld elements (%lld leaves), %.1f MiB\n",
                   frame, s.totalSeconds, s.activeLinks, s.elements, s.leaves,
                   double(s.totalBytes()) / (1 << 20));
    progress.advance();
  }
  if (!options.report.empty()) {
    nlohmann::json report = statsJson(solver.stats());
    report["method"] = "galerkin";
    report["update"] = options.update;
    report["tolerance"] = options.radiosity.tolerance;
    writeReport(report, options.report, options.scene, scene.polygonCount(), frames);
  }
  return kOk;
}

}  // namespace

int runRadiosity(const RadiosityCommandOptions& options, const CommonOptions& common) {
  if (options.update != "full")
    throw UsageError("--update " + options.update +
                     " is not available in this build (available: full; the line-space update "
                     "is a later issue)");
  if (options.solver != "hierarchical" && options.solver != "galerkin")
    throw UsageError("--solver " + options.solver +
                     " is not available (available: hierarchical, galerkin)");
  const Scene scene = loadScene(options.scene);
  const FrameRange range = parseFrameRange(options.frames, scene.frames);
  if (options.solver == "galerkin") return runGalerkin(options, common, scene, range);
  const int first = range.first, last = range.last;
  // One live scene and one solver held across frames, told each change (the solver recomputes
  // inside update() until the line-space update lands).
  DynamicScene live(scene, first);
  RadiositySolver solver(withThreads(options.radiosity, common));
  nlohmann::json frames = nlohmann::json::array();
  Progress progress("radiosity", last - first + 1, common.quiet);
  for (int frame = first; frame <= last; ++frame) {
    const int moved = buildOrStep(live, solver, frame, frame == first);
    const RadiosityStats& s = solver.stats();
    nlohmann::json entry = statsJson(s);
    entry["frame"] = frame;
    entry["seconds"] = s.totalSeconds;
    entry["moved_objects"] = moved;
    entry["converged"] = s.converged;
    frames.push_back(entry);
    if (!s.converged)
      std::fprintf(stderr,
                   "penumbra: warning: frame %d: the solution did not converge in %d iterations "
                   "(largest relative change %.3g)\n",
                   frame, s.iterations, s.residual);
    if (!common.quiet)
      std::fprintf(stderr,
                   "frame %d: %.3f s, %lld links (%lld passive), %lld elements (%lld leaves), "
                   "%lld shafts, %.1f MiB\n",
                   frame, s.totalSeconds, s.links, s.passiveLinks, s.elements, s.leaves, s.shafts,
                   double(s.totalBytes()) / (1 << 20));
    progress.advance();
  }
  if (!options.report.empty()) {
    const RadiosityStats& s = solver.stats();
    nlohmann::json report = statsJson(s);
    report["method"] = "radiosity";
    report["update"] = options.update;
    report["tolerance"] = options.radiosity.tolerance;
    writeReport(report, options.report, options.scene, scene.polygonCount(), frames);
  }
  return kOk;
}

}  // namespace penumbra::cli
