// The shared spatial structures under motion (issue "motion as data"): per step of a moving
// object, updating the live scene's grid and ray caster (DynamicScene::apply: re-pose the object,
// edit only its cells, rebuild only its BVH and the instance level) against rebuilding both at
// the new pose, side by side in one run; plus the same for a caller's arbitrary rigid moves
// (rotations, not only the keyframes' translations) and the memory of both structures.
//
// Usage: motion_bench [POLYGONS] [STEPS]  (defaults: a generated room of 100,000 polygons, 40
// steps)

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "bench_main.h"
#include "penumbra/scene/scene_generator.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/dynamic_scene.h"

namespace {

using namespace penumbra;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0 : values[values.size() / 2];
}

struct StepTimes {
  std::vector<double> updateGrid, updateRays, rebuildGrid, rebuildRays;
};

// Rebuilding both structures from scratch at the live scene's current pose: what every engine did
// every frame before the live scene (one grid and one caster per engine, fitted to the frame).
void timeRebuild(const DynamicScene& live, StepTimes& times) {
  auto start = Clock::now();
  const UniformGrid grid(live.posed());
  times.rebuildGrid.push_back(msSince(start));
  start = Clock::now();
  const RayCaster rays(live.posed());
  times.rebuildRays.push_back(msSince(start));
  if (grid.totalEntries() != live.grid().totalEntries() ||
      rays.triangleCount() != live.rays().triangleCount()) {
    std::fprintf(stderr, "motion_bench: the updated structures differ from rebuilt ones\n");
    std::exit(1);
  }
}

void report(const char* what, const StepTimes& t) {
  const double update = median(t.updateGrid) + median(t.updateRays);
  const double rebuild = median(t.rebuildGrid) + median(t.rebuildRays);
  std::printf(
      "%-28s  grid update %8.3f ms  rebuild %8.1f ms  |  rays update %8.3f ms  rebuild "
      "%8.1f ms  |  both: update %8.3f ms, rebuild %8.1f ms, ratio %6.0fx\n",
      what, median(t.updateGrid), median(t.rebuildGrid), median(t.updateRays),
      median(t.rebuildRays), update, rebuild, rebuild / std::max(update, 1e-9));
}

}  // namespace

static int benchMain(int argc, char** argv) {
  const int polygons = argc > 1 ? std::atoi(argv[1]) : 100000;
  const int steps = argc > 2 ? std::atoi(argv[2]) : 40;
  SceneGeneratorOptions generator;
  generator.targetPolygons = polygons;
  generator.frames = steps + 1;
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "penumbra-motion-bench.json";
  std::ofstream(path) << generateSceneJson(generator);
  const Scene scene = loadScene(path.string());
  std::filesystem::remove(path);

  auto start = Clock::now();
  DynamicScene live(scene, 0);
  const double buildMs = msSince(start);
  std::printf(
      "generated room: %d polygons, %zu objects (%d dynamic), %d triangles, grid %dx%dx%d "
      "(%zu entries, %.1f MiB); live scene built in %.0f ms\n",
      scene.polygonCount(), scene.objects.size(), scene.dynamicObjectCount(),
      live.rays().triangleCount(), live.grid().resolution().nx, live.grid().resolution().ny,
      live.grid().resolution().nz, live.grid().totalEntries(),
      double(live.grid().memoryBytes()) / (1 << 20), buildMs);

  // Keyframe steps of the moving box.
  StepTimes keyframes;
  for (int frame = 1; frame <= steps; ++frame) {
    const SceneChange change = live.changeToFrame(frame);
    live.apply(change);
    keyframes.updateGrid.push_back(1e3 * live.lastGridSeconds());
    keyframes.updateRays.push_back(1e3 * live.lastRaySeconds());
    timeRebuild(live, keyframes);
  }
  report("keyframe steps (box)", keyframes);

  // A caller's arbitrary rigid moves of a piece of furniture (rotations included), inside the
  // room: the viewer's drag.
  int mover = -1;
  for (int o = int(scene.objects.size()) - 1; o >= 0 && mover < 0; --o)
    if (!scene.objects[o].isDynamic() && scene.objects[o].polygons.size() >= 6 &&
        scene.objects[o].polygons.size() < 200)
      mover = o;
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  StepTimes drags;
  for (int step = 0; step < steps; ++step) {
    const Quaternion turn = Quaternion::fromAxisAngle({0, 1, 0}, 0.2 * unit(random));
    const Transform delta =
        Transform::fromTrs(Vec3{0.05 * unit(random), 0, 0.05 * unit(random)}, turn, {1, 1, 1});
    const SceneChange change = live.changeMoving(mover, delta * live.transformOf(mover));
    if (change.extentGrows) continue;  // stays in the room
    live.apply(change);
    drags.updateGrid.push_back(1e3 * live.lastGridSeconds());
    drags.updateRays.push_back(1e3 * live.lastRaySeconds());
    timeRebuild(live, drags);
  }
  char label[64];
  std::snprintf(label, sizeof label, "drags (%zu polygons)", scene.objects[mover].polygons.size());
  report(label, drags);
  std::printf("medians over %d steps; ratio = rebuild / update of grid + ray caster together\n",
              steps);
  return 0;
}

int main(int argc, char** argv) {
  return penumbra::bench::runReportingErrors("motion_bench", argc, argv, benchMain);
}
