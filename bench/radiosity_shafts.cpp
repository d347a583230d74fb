// Dynamic shaft management (Schöffel & Pomi 1999) measured side by side in one run: the same
// moves applied to solvers that differ only in their shaft policy, on one thread each:
//   all         every estimated pair keeps its occluder candidates (ShaftPolicy::kAll);
//   managed     lists made on demand and on the predicted boxes, collected by age, the shaft
//               work done in the update's own time (no worker thread);
//   unpredicted the same without movement prediction;
//   worker      managed, the shaft work on the worker thread after each update (the update's
//               time then includes any wait for the last one's work);
//   lean        worker, keeping only the empty lists beyond the update that used them
//               (ShaftManagement::keepCount 0, keepMoversParents false).
// After every move each solver draws a frame (its leaf mesh, while the worker works) and the
// solutions are compared bit for bit with the `all` one (shafts change cost, never results). The
// moves: the scene's keyframes forward and back, then a random walk (a smooth one: each moving
// object keeps a velocity that a random push changes a little at every move, reflected at the
// room's walls, and turns a little), printing the memory curve every 100 moves. Reported as the
// paper's Table 2: shafts at the old and new position, shaft tests, made on the fly, already there,
// made on prediction, deleted by collection, lists held, their memory against every pair's,
// traversal and shaft-generation time.
//
// Usage: radiosity_shafts [--moves N] [--repeat R] [--tolerance T] [SCENE]
//        (default: the furnished room, 1,000 moves, the keyframes walked once)

#include <algorithm>
#include <cstdio>
#include <cstdlib>
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
using bench::mean;
using bench::median;

struct Policy {
  const char* name;
  GalerkinOptions options;
};

// What one policy's solver did over the moves.
struct Record {
  std::vector<double> seconds, traverse, shaftSeconds, wait, drawing, heldShare;
  long long atOld = 0, atNew = 0, tests = 0, made = 0, there = 0, predicted = 0, collected = 0;
  long long remade = 0, counted = 0;
  long long predictionTests = 0;
  long long madeAfterFirst = 0, testsAfterFirst = 0;  // from the 10th move on
  std::size_t maxShaftBytes = 0, maxAllBytes = 0;
  int differences = 0;
};

// A smooth random walk of every keyframed object (see the file's comment).
class SmoothWalk {
 public:
  SmoothWalk(const Scene& scene, const DynamicScene& live) : room_(live.extent()) {
    for (int o = 0; o < int(scene.objects.size()); ++o) {
      if (!scene.objects[o].isDynamic()) continue;
      Box3 local;
      for (const Polygon3& polygon : scene.objects[o].polygons)
        for (const Vec3& v : polygon) local.extend(v);
      Mover m;
      m.object = o;
      m.localCentre = local.center();
      m.at = live.transformOf(o).applyToPoint(local.center());
      m.rotation = Quaternion::identity();
      movers_.push_back(m);
    }
  }
  bool empty() const { return movers_.empty(); }
  SceneChange next(const DynamicScene& live) {
    Mover& m = movers_[step_++ % movers_.size()];
    const Vec3 d = room_.diagonal();
    const double speed = 0.01 * length(d);
    for (int attempt = 0; attempt < 100; ++attempt) {
      Vec3 velocity = m.velocity + Vec3{unit_(random_), unit_(random_), unit_(random_)} * speed;
      if (length(velocity) > 2 * speed) velocity = velocity * (2 * speed / length(velocity));
      Vec3 at = m.at + velocity;
      // Reflected at a box a little inside the room, so that it stays inside.
      const Box3 inner{room_.min + d * 0.2, room_.max - d * 0.2};
      for (int axis = 0; axis < 3; ++axis)
        if (at[axis] < inner.min[axis] || at[axis] > inner.max[axis]) {
          velocity[axis] = -velocity[axis];
          at[axis] = m.at[axis] + velocity[axis];
        }
      const Quaternion turn = Quaternion::fromAxisAngle({0, 1, 0}, 0.03 * unit_(random_));
      const Quaternion rotation = turn * m.rotation;
      const Transform pose =
          Transform::fromTrs(at, rotation, {1, 1, 1}) *
          Transform::fromTrs(m.localCentre * -1.0, Quaternion::identity(), {1, 1, 1});
      SceneChange change = live.changeMoving(m.object, pose);
      if (change.extentGrows) continue;
      m.velocity = velocity;
      m.at = at;
      m.rotation = rotation;
      return change;
    }
    return live.changeMoving(m.object, live.transformOf(m.object));
  }

 private:
  struct Mover {
    int object = 0;
    Vec3 localCentre, at, velocity;
    Quaternion rotation;
  };
  Box3 room_;
  std::vector<Mover> movers_;
  size_t step_ = 0;
  std::mt19937_64 random_{17};
  std::uniform_real_distribution<double> unit_{-1, 1};
};

}  // namespace

static int benchMain(int argc, char** argv) {
  int moves = 1000, repeat = 1;
  double tolerance = GalerkinOptions{}.tolerance;
  std::string path = PENUMBRA_SOURCE_DIR "/scenes/chair-room/furnished-room.json";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--moves" && i + 1 < argc)
      moves = std::max(0, std::atoi(argv[++i]));
    else if (arg == "--repeat" && i + 1 < argc)
      repeat = std::max(0, std::atoi(argv[++i]));
    else if (arg == "--tolerance" && i + 1 < argc)
      tolerance = std::atof(argv[++i]);
    else
      path = arg;
  }
  const Scene scene = loadScene(path);
  GalerkinOptions base;
  base.tolerance = tolerance;
  base.threads = 1;
  std::vector<Policy> policies(4, Policy{"", base});
  policies[0].name = "all";
  policies[0].options.shafts = ShaftPolicy::kAll;
  policies[1].name = "managed";
  policies[1].options.management.workerThread = false;
  policies[2].name = "unpredicted";
  policies[2].options.management.workerThread = false;
  policies[2].options.management.prediction = false;
  policies[3].name = "worker";
  policies.push_back(policies[3]);
  policies[4].name = "lean";
  policies[4].options.management.keepCount = 0;
  policies[4].options.management.keepMoversParents = false;
  std::printf(
      "%s (%d polygons), tolerance %g, one thread per solver; %d keyframe walks, %d moves\n",
      path.c_str(), scene.polygonCount(), tolerance, repeat, moves);

  DynamicScene live(scene, 0);
  std::vector<std::unique_ptr<GalerkinRadiosity>> solvers;
  for (const Policy& p : policies) {
    solvers.push_back(std::make_unique<GalerkinRadiosity>(p.options));
    solvers.back()->build(live);
  }
  std::vector<Record> records(policies.size());
  SmoothWalk walk(scene, live);
  std::vector<SceneChange> keyframes;
  int move = 0;
  std::size_t triangles = 0;  // drawn (kept, so the drawing is not optimized away)
  const auto step = [&](const SceneChange& change) {
    live.apply(change);
    for (size_t p = 0; p < solvers.size(); ++p) {
      const Stopwatch watch;
      solvers[p]->update(live, change);
      const double seconds = watch.seconds();
      // A frame's drawing: the solution as drawn, its leaves' triangles with smoothed corners
      // (what a viewer takes after an update), made beside the worker's shaft work.
      const Stopwatch drawing;
      const RadiosityMesh mesh = solvers[p]->leafMesh();
      triangles += mesh.indices.size() / 3;
      const double drawn = drawing.seconds();
      const Stopwatch join;
      const GalerkinUpdateStats& u = solvers[p]->lastUpdate();  // waits for the worker
      const double waited = join.seconds();
      const GalerkinStats& s = solvers[p]->stats();
      Record& r = records[p];
      // The worker does the shaft work after the update returns, beside the drawing: what the
      // frame waits for it after the drawing counts as the update's; the other policies' calls
      // include the work.
      r.seconds.push_back(seconds + waited);
      r.traverse.push_back(u.traverseSeconds);
      r.shaftSeconds.push_back(u.shaftSeconds);
      r.wait.push_back(waited + u.shaftWaitSeconds);
      r.drawing.push_back(drawn);
      r.atOld += u.shaftsAtOld;
      r.atNew += u.shaftsAtNew;
      r.tests += u.shaftTests;
      r.made += u.shaftsMade;
      r.there += u.shaftsThere;
      r.remade += u.shaftsRemade;
      r.counted += u.shaftsCounted;
      r.predicted += u.shaftsPredicted;
      r.predictionTests += u.predictionTests;
      r.collected += u.shaftsCollected;
      if (move >= 10) {
        r.madeAfterFirst += u.shaftsMade;
        r.testsAfterFirst += u.shaftTests;
      }
      r.maxShaftBytes = std::max(r.maxShaftBytes, s.shaftBytes);
      r.maxAllBytes = std::max(r.maxAllBytes, s.allShaftBytes);
      r.heldShare.push_back(double(s.shaftBytes) /
                            double(std::max<std::size_t>(1, s.allShaftBytes)));
      if (p > 0) {
        const std::string difference = solvers[p]->differenceFrom(*solvers[0]);
        if (!difference.empty() && r.differences++ < 3)
          std::printf("  move %d: %s differs from all: %s\n", move, policies[p].name,
                      difference.c_str());
      }
    }
    ++move;
    if (move % 100 == 0) {
      std::printf("  after %4d moves:", move);
      for (size_t p = 0; p < solvers.size(); ++p) {
        const GalerkinStats& s = solvers[p]->stats();
        std::printf("  %s %.1f MiB (shafts %.2f)", policies[p].name,
                    double(s.totalBytes()) / (1 << 20), double(s.shaftBytes) / (1 << 20));
      }
      std::printf("\n");
    }
  };
  for (int r = 0; r < repeat && scene.frames > 1; ++r) {
    for (int f = 1; f < scene.frames; ++f) step(live.changeToFrame(f));
    for (int f = scene.frames - 2; f >= 0; --f) step(live.changeToFrame(f));
  }
  for (int i = 0; i < moves && !walk.empty(); ++i) step(walk.next(live));

  const double allSeconds = median(records[0].seconds);
  std::printf("\n  %-12s %9s %7s %9s %9s %7s %7s %7s %7s %7s %7s %7s %7s %8s %8s %8s %8s %6s\n",
              "policy", "update", "extra", "traverse", "shaftgen", "at old", "at new", "tests",
              "on fly", "anew", "there", "count", "predict", "collect", "held", "held/all", "max",
              "fly/t");
  int failures = 0;
  for (size_t p = 0; p < policies.size(); ++p) {
    const Record& r = records[p];
    const double n = double(std::max<size_t>(1, r.seconds.size()));
    failures += r.differences;
    std::printf(
        "  %-12s %7.2fms %6.1f%% %7.2fms %7.2fms %7.0f %7.0f %7.0f %7.0f %7.0f %7.0f %7.0f %7.0f "
        "%8.0f %7.2fM %7.2f%% %7.2f%% %5.1f%%\n",
        policies[p].name, 1e3 * median(r.seconds), 100 * (median(r.seconds) / allSeconds - 1),
        1e3 * median(r.traverse), 1e3 * median(r.shaftSeconds), r.atOld / n, r.atNew / n,
        r.tests / n, r.made / n, r.remade / n, r.there / n, r.counted / n, r.predicted / n,
        r.collected / n, double(solvers[p]->stats().shaftBytes) / (1 << 20),
        100 * mean(r.heldShare),
        100 * double(r.maxShaftBytes) / double(std::max<std::size_t>(1, r.maxAllBytes)),
        100 * double(r.madeAfterFirst) / double(std::max(1LL, r.testsAfterFirst)));
  }
  std::printf(
      "  (per move: medians of times, means of counts; held/all: shaft bytes held over every "
      "pair's, mean over the moves; max: the largest held over the largest every-pair; on fly: "
      "lists made because they were not kept; anew: made again because an end or the parent's "
      "list changed, under any policy; count: estimated from how many candidates alone; fly/t: "
      "on fly over shaft tests from the 10th move on)\n");
  std::printf("  (%zu triangles drawn in all)\n", triangles);
  for (size_t p = 0; p < policies.size(); ++p)
    std::printf("  %-12s drawing %.2f ms, then waited for the shaft work %.2f ms (medians)\n",
                policies[p].name, 1e3 * median(records[p].drawing), 1e3 * median(records[p].wait));
  std::printf("  results: %s\n",
              failures ? "DIFFERENT from all" : "bit-identical to all at every move");
  return failures ? 1 : 0;
}

int main(int argc, char** argv) {
  return penumbra::bench::runReportingErrors("radiosity_shafts", argc, argv, benchMain);
}
