// Radiosity under motion: per keyframe step, GalerkinRadiosity::update (the line-space update) on
// the live scene against a fresh build at the same pose, side by side in one run, on one thread;
// with the update's stages, what it touched, and verifyLinks() after every step (outside the
// timings). The keyframes are walked forward and back `--repeat` times; times are medians.
//
// `--back-to-back`: the walk's updates run one after the other, nothing between them (as an
// interactive session runs them), and then, in the same run, fresh builds at each keyframe; the
// last update is verified. (Measured in session 24: no faster than with the builds between.)
//
// Usage: radiosity_update [--repeat N] [--tolerance T] [--updates-only | --back-to-back]
//                         [--random-moves N] [--shafts all|managed]
//                         [SCENE...]  (default: the
// furnished room, the chair room, the Cornell box)

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "bench_main.h"
#include "bench_statistics.h"
#include "penumbra/base/stopwatch.h"
#include "penumbra/radiosity/galerkin/galerkin_radiosity.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/dynamic_scene.h"

namespace {

using namespace penumbra;
using bench::median;

struct StepFigures {
  std::vector<double> update, repose, traverse, walk, refine, solve, full;
  std::vector<bool> compacted;  // the update compacted the pairs (then the next has nothing kept)
  long long met = 0, endMoved = 0, reestimated = 0, rays = 0, reused = 0, links = 0;
};

// What runs beside the timed updates.
enum class Mode {
  kInterleaved,  // after each update: verification and a fresh build at the same pose
  kUpdatesOnly,  // nothing (for profiling the update)
  kBackToBack,   // after the walk: verification of the last update, fresh builds at each pose
};

// Returns how many steps failed verification.
int benchScene(const std::string& path, int repeat, double tolerance, Mode mode,
               ShaftPolicy shafts) {
  const Scene scene = loadScene(path);
  GalerkinOptions options;
  options.tolerance = tolerance;
  options.threads = 1;
  options.shafts = shafts;
  std::printf("%s (%d polygons, %d frames), tolerance %g, one thread\n", path.c_str(),
              scene.polygonCount(), scene.frames, tolerance);
  if (scene.frames < 2) {
    std::printf("  no motion\n");
    return 0;
  }
  DynamicScene live(scene, 0);
  GalerkinRadiosity solver(options);
  solver.build(live);
  std::printf("  frame 0 built in %.3f s: %lld links, %lld elements, %.1f MiB\n",
              solver.stats().totalSeconds, solver.stats().activeLinks, solver.stats().elements,
              double(solver.stats().totalBytes()) / (1 << 20));
  // Steps keyed by (from, to).
  std::map<std::pair<int, int>, StepFigures> steps;
  std::vector<int> walk;
  for (int r = 0; r < repeat; ++r) {
    for (int f = 1; f < scene.frames; ++f) walk.push_back(f);
    for (int f = scene.frames - 2; f >= 0; --f) walk.push_back(f);
  }
  int failures = 0;
  int from = 0;
  for (int to : walk) {
    const SceneChange change = live.changeToFrame(to);
    live.apply(change);
    const Stopwatch watch;
    solver.update(live, change);
    solver.lastUpdate();  // the shaft work too, which a worker thread does after the update
    const double seconds = watch.seconds();
    StepFigures& s = steps[{from, to}];
    const GalerkinUpdateStats& u = solver.lastUpdate();
    s.update.push_back(seconds);
    s.compacted.push_back(u.compacted);
    s.repose.push_back(u.reposeSeconds);
    s.traverse.push_back(u.traverseSeconds);
    s.walk.push_back(u.walkSeconds);
    s.refine.push_back(u.refineSeconds);
    s.solve.push_back(u.solveSeconds);
    s.met = u.met;
    s.endMoved = u.endMoved;
    s.reestimated = u.reestimated;
    s.rays = solver.stats().visibilityRays;
    s.reused = u.reusedVisibility;
    s.links = solver.stats().activeLinks;
    if (u.rebuilt) std::printf("  step %d->%d rebuilt: %s\n", from, to, u.rebuildReason);
    from = to;
    if (mode != Mode::kInterleaved) continue;
    const std::string difference = solver.verifyLinks();
    if (!difference.empty()) {
      ++failures;
      std::printf("  step to %d: VERIFICATION FAILED: %s\n", to, difference.c_str());
    }
    GalerkinRadiosity fresh(options);
    fresh.build(live);
    s.full.push_back(fresh.stats().totalSeconds);
  }
  if (mode == Mode::kBackToBack) {
    const std::string difference = solver.verifyLinks();
    if (!difference.empty()) {
      ++failures;
      std::printf("  the last update: VERIFICATION FAILED: %s\n", difference.c_str());
    }
    std::vector<std::vector<double>> fullAt(size_t(scene.frames));
    for (int r = 0; r < repeat; ++r)
      for (int f = 0; f < scene.frames; ++f) {
        const DynamicScene at(scene, f);
        GalerkinRadiosity fresh(options);
        fresh.build(at);
        fullAt[size_t(f)].push_back(fresh.stats().totalSeconds);
      }
    for (auto& [key, s] : steps) s.full = fullAt[size_t(key.second)];
  }
  std::printf("  %-7s %9s %9s %9s %9s %9s %9s %9s %7s %7s %7s %7s %8s %7s\n", "step", "update",
              "repose", "traverse", "(walk)", "refine", "solve", "full", "ratio", "met", "ends",
              "rays", "reused", "links");
  std::vector<double> updates, fulls, traverses, walks;
  for (const auto& [key, s] : steps) {
    const double update = median(s.update), full = median(s.full);
    updates.push_back(update);
    fulls.push_back(full);
    traverses.push_back(median(s.traverse));
    walks.push_back(median(s.walk));
    std::printf(
        "  %2d->%-3d %8.1fms %8.2fms %8.1fms %8.2fms %8.1fms %8.1fms %8.0fms %6.1fx %7lld %7lld "
        "%7lld %8lld %7lld\n",
        key.first, key.second, 1e3 * update, 1e3 * median(s.repose), 1e3 * median(s.traverse),
        1e3 * median(s.walk), 1e3 * median(s.refine), 1e3 * median(s.solve), 1e3 * full,
        full / update, s.met, s.endMoved, s.rays, s.reused, s.links);
  }
  // Each step's updates in the order they ran (the first of 0->1 follows the build: no list
  // kept but the root's, nothing kept from a last move; "c": the update compacted the pairs,
  // which renumbers them and drops what the solve and the walk kept), to tell a slow step from
  // a slow moment.
  if (repeat > 1) {
    std::printf("  each update in order of the runs (ms; c: compacted):\n");
    for (const auto& [key, s] : steps) {
      std::printf("  %2d->%-3d", key.first, key.second);
      for (size_t k = 0; k < s.update.size(); ++k)
        std::printf(" %6.1f%s", 1e3 * s.update[k], s.compacted[k] ? "c" : " ");
      std::printf("\n");
    }
  }
  std::printf(
      "  median over steps: update %.1f ms (traversal %.1f ms, of it the walk %.2f ms), full "
      "%.0f ms: %.1fx; verification %s\n",
      1e3 * median(updates), 1e3 * median(traverses), 1e3 * median(walks), 1e3 * median(fulls),
      median(fulls) / median(updates),
      mode == Mode::kUpdatesOnly  ? "not run"
      : failures                  ? "FAILED"
      : mode == Mode::kBackToBack ? "identical after the last update"
                                  : "identical at every step");
  return failures;
}

// A seeded random walk of caller moves (rotations and translations of every keyframed object,
// each kept inside the scene's extent), verifyLinks() after every one; returns the failures.
int randomMoves(const std::string& path, int moves, double tolerance, ShaftPolicy shafts) {
  const Scene scene = loadScene(path);
  GalerkinOptions options;
  options.tolerance = tolerance;
  options.threads = 1;
  options.shafts = shafts;
  DynamicScene live(scene, 0);
  GalerkinRadiosity solver(options);
  solver.build(live);
  std::vector<int> movers;
  for (int o = 0; o < int(scene.objects.size()); ++o)
    if (scene.objects[o].isDynamic()) movers.push_back(o);
  if (movers.empty()) return 0;
  std::mt19937_64 random(17);
  std::uniform_real_distribution<double> unit(-1, 1);
  const Box3 room = live.extent();
  int failures = 0, rebuilt = 0;
  const double builtMiB = double(solver.stats().totalBytes()) / (1 << 20);
  std::vector<double> seconds;
  for (int step = 0; step < moves; ++step) {
    const int object = movers[step % movers.size()];
    Box3 local;
    for (const Polygon3& polygon : scene.objects[object].polygons)
      for (const Vec3& v : polygon) local.extend(v);
    SceneChange change;
    for (int attempt = 0; attempt < 100; ++attempt) {
      const Vec3 d = room.diagonal();
      const Vec3 axis =
          normalize(Vec3{unit(random), unit(random), unit(random)} + Vec3{0, 1e-3, 0});
      const Transform pose =
          Transform::fromTrs(
              room.center() +
                  Vec3{unit(random) * d.x, unit(random) * d.y, unit(random) * d.z} * 0.3,
              Quaternion::fromAxisAngle(axis, 3.2 * unit(random)), {1, 1, 1}) *
          Transform::fromTrs(local.center() * -1.0, Quaternion::identity(), {1, 1, 1});
      change = live.changeMoving(object, pose);
      if (!change.extentGrows) break;
    }
    live.apply(change);
    const Stopwatch watch;
    solver.update(live, change);
    solver.lastUpdate();  // the shaft work too, which a worker thread does after the update
    seconds.push_back(watch.seconds());
    rebuilt += solver.lastUpdate().rebuilt ? 1 : 0;
    const std::string difference = solver.verifyLinks();
    if (!difference.empty() && failures++ < 5)
      std::printf("  move %d: VERIFICATION FAILED: %s\n", step, difference.c_str());
    // Memory along the walk, beside a fresh build's at the same pose (what the update's history
    // adds to it).
    if ((step + 1) % std::max(1, moves / 10) == 0) {
      GalerkinRadiosity fresh(options);
      fresh.build(live);
      const GalerkinStats &u = solver.stats(), &f = fresh.stats();
      std::printf(
          "  after %4d moves: %6.1f MiB, %7lld elements, %8lld pairs; a fresh build: %6.1f MiB, "
          "%7lld elements, %8lld pairs\n",
          step + 1, double(u.totalBytes()) / (1 << 20), u.elements, u.activeLinks + u.passiveLinks,
          double(f.totalBytes()) / (1 << 20), f.elements, f.activeLinks + f.passiveLinks);
    }
  }
  std::printf(
      "%s: %d random moves, median update %.1f ms, %d rebuilt, %d differ from fresh "
      "estimates; memory %.1f MiB after the build, %.1f MiB at the end\n",
      path.c_str(), moves, 1e3 * median(seconds), rebuilt, failures, builtMiB,
      double(solver.stats().totalBytes()) / (1 << 20));
  return failures;
}

}  // namespace

static int benchMain(int argc, char** argv) {
  int repeat = 3;
  Mode mode = Mode::kInterleaved;
  int moves = 0;  // --random-moves N: the random walk instead of the keyframes
  double tolerance = GalerkinOptions{}.tolerance;
  ShaftPolicy shafts = GalerkinOptions{}.shafts;
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repeat" && i + 1 < argc)
      repeat = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--random-moves" && i + 1 < argc)
      moves = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--shafts" && i + 1 < argc)
      shafts = std::string(argv[++i]) == "all" ? ShaftPolicy::kAll : ShaftPolicy::kManaged;
    else if (arg == "--updates-only")
      mode = Mode::kUpdatesOnly;
    else if (arg == "--back-to-back")
      mode = Mode::kBackToBack;
    else if (arg == "--tolerance" && i + 1 < argc)
      tolerance = std::atof(argv[++i]);
    else
      scenes.push_back(arg);
  }
  if (scenes.empty())
    scenes = {PENUMBRA_SOURCE_DIR "/scenes/chair-room/furnished-room.json",
              PENUMBRA_SOURCE_DIR "/scenes/chair-room/chair-room.json",
              PENUMBRA_SOURCE_DIR "/scenes/cornell-box/cornell-box.json"};
  int failures = 0;
  for (const std::string& scene : scenes)
    failures += moves > 0 ? randomMoves(scene, moves, tolerance, shafts)
                          : benchScene(scene, repeat, tolerance, mode, shafts);
  return failures ? 1 : 0;
}

int main(int argc, char** argv) {
  return penumbra::bench::runReportingErrors("radiosity_update", argc, argv, benchMain);
}
