// `penumbra radiosity SCENE [--frames A:B] [--update full|linespace|verify]
// [--solver hierarchical|galerkin] [--tolerance T] [--frame-budget MS] --report R.json`: the
// radiosity solution over a range of frames, with per-frame statistics.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

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
            {"final", s.finalBytes},
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
          {"refinement_passes", s.passes},
          {"settled", s.settled},
          {"refine_seconds", s.refineSeconds},
          {"solve_seconds", s.solveSeconds},
          {"shafts", s.shafts},
          {"shaft_bytes", s.shaftBytes},
          {"all_shaft_bytes", s.allShaftBytes},
          {"memory_bytes",
           {{"clusters", s.clusterBytes},
            {"elements", s.elementBytes},
            {"links", s.linkBytes},
            {"shafts", s.shaftBytes},
            {"solve", s.solveBytes},
            {"total", s.totalBytes()}}}};
}

nlohmann::json updateJson(const GalerkinUpdateStats& u) {
  nlohmann::json j = {{"rebuilt", u.rebuilt},
                      {"moved_elements", u.movedElements},
                      {"cover_changed", u.coverChanged},
                      {"clusters_changed", u.clustersChanged},
                      {"shaft_tests", u.shaftTests},
                      {"links_met", u.met},
                      {"end_moved", u.endMoved},
                      {"cover_only", u.coverOnly},
                      {"reestimated", u.reestimated},
                      {"reused_visibility", u.reusedVisibility},
                      {"refined", u.refined},
                      {"cleaned_up", u.cleanedUp},
                      {"created", u.created},
                      {"dropped", u.dropped},
                      {"added_by_radiosity_pass", u.laterSplits},
                      {"cleaned_up_by_radiosity_pass", u.laterCleanUps},
                      {"deferred_splits", u.deferredSplits},
                      {"over_budget", u.overBudget},
                      {"shafts",
                       {{"at_old_position", u.shaftsAtOld},
                        {"at_new_position", u.shaftsAtNew},
                        {"made_on_the_fly", u.shaftsMade},
                        {"already_there", u.shaftsThere},
                        {"made_anew", u.shaftsRemade},
                        {"counted_only", u.shaftsCounted},
                        {"prediction_tests", u.predictionTests},
                        {"made_on_prediction", u.shaftsPredicted},
                        {"collected", u.shaftsCollected},
                        {"seconds", u.shaftSeconds},
                        {"wait_seconds", u.shaftWaitSeconds}}},
                      {"stage_seconds",
                       {{"repose", u.reposeSeconds},
                        {"traverse", u.traverseSeconds},
                        {"walk", u.walkSeconds},
                        {"refine", u.refineSeconds},
                        {"solve", u.solveSeconds},
                        {"shafts", u.shaftSeconds}}}};
  if (u.rebuilt) j["rebuild_reason"] = u.rebuildReason;
  return j;
}

// How far the updated solution is from a fresh one at the same pose: the relative L2 difference
// of the total irradiance at the fresh solution's leaf centroids (area-weighted).
double relativeDifference(const GalerkinRadiosity& updated, const GalerkinRadiosity& fresh) {
  double difference = 0, norm = 0;
  for (const GalerkinRadiosity::GElement& e : fresh.elements()) {
    if (!e.isLeaf() || e.cover == GalerkinRadiosity::GElement::kCovered) continue;
    const Vec3 c = e.shape.centroid();
    const auto a = updated.sample(c, e.shape.normal), b = fresh.sample(c, e.shape.normal);
    if (!a || !b) continue;
    const Rgb d = a->total() - b->total(), t = b->total();
    difference += e.area * (d.r * d.r + d.g * d.g + d.b * d.b);
    norm += e.area * (t.r * t.r + t.g * t.g + t.b * t.b);
  }
  return norm > 0 ? std::sqrt(difference / norm) : 0;
}

double balance(const GalerkinRadiosity& solver) {
  return solver.absorbedPower().average() / std::max(solver.emittedPower().average(), 1e-300);
}

// The Galerkin core over the frames: built at the first, then each step by a fresh build
// (--update full) or the line-space update (linespace; verify also checks every pair and
// compares with a fresh build at the same pose).
int runGalerkin(const RadiosityCommandOptions& options, const CommonOptions& common,
                const Scene& scene, const FrameRange& range) {
  if (options.update != "full" && options.update != "linespace" && options.update != "verify")
    throw UsageError("--update " + options.update +
                     " is not available (available: full, linespace, verify)");
  const bool incremental = options.update != "full";
  const bool verify = options.update == "verify";
  DynamicScene live(scene, range.first);
  GalerkinOptions solverOptions = galerkinOptions(options.radiosity, common);
  solverOptions.frameBudgetSeconds = options.frameBudgetMs / 1000;
  if (options.shafts == "all") solverOptions.shafts = ShaftPolicy::kAll;
  if (options.shafts == "managed") solverOptions.shafts = ShaftPolicy::kManaged;
  GalerkinRadiosity solver(solverOptions);
  nlohmann::json frames = nlohmann::json::array();
  Progress progress("radiosity (galerkin)", range.last - range.first + 1, common.quiet);
  for (int frame = range.first; frame <= range.last; ++frame) {
    int moved = 0;
    if (incremental || frame == range.first) {
      moved = buildOrStep(live, solver, frame, frame == range.first);
    } else {
      const SceneChange change = live.changeToFrame(frame);
      live.apply(change);
      moved = int(change.moves.size());
      solver.build(live);
    }
    const GalerkinStats& s = solver.stats();
    nlohmann::json entry = statsJson(s);
    entry["frame"] = frame;
    entry["seconds"] = s.totalSeconds;
    entry["moved_objects"] = moved;
    entry["absorbed_over_emitted"] = balance(solver);
    if (incremental && frame != range.first) entry["update"] = updateJson(solver.lastUpdate());
    std::string freshLine;
    if (verify && frame != range.first) {
      const std::string difference = solver.verifyLinks();
      GalerkinRadiosity fresh(galerkinOptions(options.radiosity, common));
      fresh.build(live);
      const double l2 = relativeDifference(solver, fresh);
      const GalerkinRadiosity::PendingRefinement pending = solver.pendingRefinement(),
                                                 freshPending = fresh.pendingRefinement();
      entry["fresh"] = {{"seconds", fresh.stats().totalSeconds},
                        {"active_links", fresh.stats().activeLinks},
                        {"elements", fresh.stats().elements},
                        {"absorbed_over_emitted", balance(fresh)},
                        {"relative_l2_difference", l2},
                        {"pending_splits", freshPending.splits},
                        {"pending_clean_ups", freshPending.cleanUps}};
      // What one more refinement pass would change, here and in the fresh build.
      entry["pending_splits"] = pending.splits;
      entry["pending_clean_ups"] = pending.cleanUps;
      char line[160];
      std::snprintf(line, sizeof line, "; fresh build: %.3f s, %lld links, L2 difference %.4f",
                    fresh.stats().totalSeconds, fresh.stats().activeLinks, l2);
      freshLine = line;
      std::string failure = difference;
      // An update ends with a pass that changed nothing; one more must change nothing either.
      if (failure.empty() && s.settled && (pending.splits != 0 || pending.cleanUps != 0))
        failure = "one more refinement pass would split " + std::to_string(pending.splits) +
                  " links and clean up " + std::to_string(pending.cleanUps) + " split pairs";
      if (!failure.empty()) {
        std::fprintf(stderr, "penumbra: verification failed at frame %d: %s\n", frame,
                     failure.c_str());
        return kVerificationFailed;
      }
      if (!s.settled)
        std::fprintf(stderr,
                     "penumbra: frame %d: refinement stopped at its pass budget before a pass "
                     "changed nothing (%lld splits and %lld clean-ups pending)\n",
                     frame, pending.splits, pending.cleanUps);
    }
    frames.push_back(entry);
    if (!common.quiet) {
      std::fprintf(stderr, "frame %d: %.3f s, %lld links, %lld elements (%lld leaves), %.1f MiB",
                   frame, s.totalSeconds, s.activeLinks, s.elements, s.leaves,
                   double(s.totalBytes()) / (1 << 20));
      std::fprintf(stderr, ", shafts %.2f MiB of %.2f MiB", double(s.shaftBytes) / (1 << 20),
                   double(s.allShaftBytes) / (1 << 20));
      if (incremental && frame != range.first) {
        const GalerkinUpdateStats& u = solver.lastUpdate();
        std::fprintf(stderr, "; %lld shaft tests, %lld pairs met, %lld split, %lld cleaned up",
                     u.shaftTests, u.met, u.refined, u.cleanedUp);
        if (u.overBudget)
          std::fprintf(stderr, ", over budget: %lld splits deferred", u.deferredSplits);
      }
      std::fprintf(stderr, "%s\n", freshLine.c_str());
    }
    progress.advance();
  }
  if (!options.report.empty()) {
    nlohmann::json report = statsJson(solver.stats());
    report["method"] = "galerkin";
    report["update"] = options.update;
    report["shaft_policy"] = solverOptions.shafts == ShaftPolicy::kAll ? "all" : "managed";
    report["tolerance"] = options.radiosity.tolerance;
    writeReport(report, options.report, options.scene, scene.polygonCount(), frames);
  }
  return kOk;
}

}  // namespace

int runRadiosity(const RadiosityCommandOptions& given, const CommonOptions& common) {
  RadiosityCommandOptions options = given;
  if (options.solver.empty())
    options.solver =
        options.update != "full" || !options.shafts.empty() ? "galerkin" : "hierarchical";
  if (options.solver != "hierarchical" && options.solver != "galerkin")
    throw UsageError("--solver " + options.solver +
                     " is not available (available: hierarchical, galerkin)");
  if (options.solver == "hierarchical" && options.update != "full")
    throw UsageError("--update " + options.update +
                     " is not available for --solver hierarchical (available: full; the "
                     "line-space update is --solver galerkin's)");
  if (!options.shafts.empty() && options.shafts != "all" && options.shafts != "managed")
    throw UsageError("--shafts " + options.shafts + " is not available (available: all, managed)");
  if (options.solver == "hierarchical" && options.shafts == "managed")
    throw UsageError(
        "--shafts managed is not available for --solver hierarchical (it has no line-space "
        "update; available: all)");
  if (options.frameBudgetMs > 0 && options.update != "linespace")
    throw UsageError(
        "--frame-budget needs --update linespace (verify compares a hierarchy "
        "that does not depend on the machine's speed)");
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
    report["shaft_policy"] = "all";
    report["tolerance"] = options.radiosity.tolerance;
    writeReport(report, options.report, options.scene, scene.polygonCount(), frames);
  }
  return kOk;
}

}  // namespace penumbra::cli
