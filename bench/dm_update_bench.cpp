// The exact soft shadows under motion: per frame step, DiscontinuityMeshEngine::update on the live
// scene against a full build at the same pose, side by side in one run, with what the update kept
// (receiver meshes, faces) and a check that both give the same irradiance mesh bit for bit.
//
// Usage: dm_update_bench [SCENE...]  (default: desk-145, desk-475, the chair room, and a generated
// 1,000-polygon room with 5 frames)
//        dm_update_bench --steps N SCENE  one full build, then N frame steps by update alone, the
// frames walked forth and back (1, 2, ..., last, last-1, ..., 0, 1, ...): the median step and the
// median of each stage, for profiling the update without full builds beside it
//        dm_update_bench --scale [N,N,...]  generated rooms of these many polygons (default 1,000
// and 10,000; seed 1, 4 frames, the same 0.15 m box moving above the central desk): one full build
// each, then the box's steps by update alone (no full build beside them: a 10,000-polygon room's
// takes a minute and a half), each step's processor time and stages, the median step per room and
// how much it grows from the first room to each other.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_statistics.h"
#include "penumbra/dm/irradiance_mesh.h"
#include "penumbra/scene/scene_generator.h"
#include "penumbra/scene/scene_loader.h"

namespace {

using namespace penumbra;
using bench::median;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The process's processor time: the engine runs on one thread, and on a shared machine this
// varies far less than the wall clock.
double cpuSeconds() {
  return double(std::clock()) / CLOCKS_PER_SEC;
}

void benchScene(const std::string& name, const Scene& scene) {
  std::printf("%s (%d polygons, %d frames)\n", name.c_str(), scene.polygonCount(), scene.frames);
  DynamicScene live(scene, 0);
  DiscontinuityMeshEngine engine;
  auto start = Clock::now();
  engine.build(live);
  std::printf("  frame 0: built in %.3f s, %lld faces\n", secondsSince(start),
              engine.stats().meshFaces);
  double updateTotal = 0, fullTotal = 0;
  std::vector<double> updateCpu, fullCpu;
  for (int frame = 1; frame < scene.frames; ++frame) {
    const SceneChange change = live.changeToFrame(frame);
    start = Clock::now();
    double cpu = cpuSeconds();
    live.apply(change);
    engine.update(live, change);
    const double update = secondsSince(start);
    updateCpu.push_back(cpuSeconds() - cpu);
    const DmStats s = engine.stats();
    start = Clock::now();
    cpu = cpuSeconds();
    const DynamicScene scratch(scene, frame);
    DiscontinuityMeshEngine full;
    full.build(scratch);
    const double rebuild = secondsSince(start);
    fullCpu.push_back(cpuSeconds() - cpu);
    const bool identical =
        !firstDifference(buildIrradianceMesh(engine), buildIrradianceMesh(full)).has_value();
    updateTotal += update;
    fullTotal += rebuild;
    std::printf(
        "  frame %d: update %.3f s, full %.3f s (x%.2f; processor time %.3f s vs %.3f s); kept "
        "%lld casts (%lld recut by the "
        "mover), %lld traces, %lld of %lld EEE candidate cuts, %lld of "
        "%lld meshes (%lld edited: %lld surfaces out, %lld in; %lld swept again), reused %lld of "
        "%lld faces; stages "
        "s: surfaces %.3f casting %.3f EEE %.3f meshing %.3f "
        "backprojections %.3f verification %.3f; %s\n",
        frame, update, rebuild, rebuild / update, updateCpu.back(), fullCpu.back(),
        s.keptCasts + s.recastMovedCasts, s.recastMovedCasts, s.keptTraces, s.keptCandidateCuts,
        s.keptCandidateCuts + s.examinedCandidateCuts, s.keptMeshes,
        s.keptMeshes + s.rebuiltMeshes + s.editedMeshes, s.editedMeshes, s.removedSurfaces,
        s.insertedSurfaces, s.resweptMeshes, s.reusedFaces, s.meshFaces, s.secondsSurfaces,
        s.secondsCasting, s.secondsEee, s.secondsMeshing, s.secondsBackprojections,
        s.secondsVerification, identical ? "identical to full" : "DIFFERS FROM FULL");
  }
  if (scene.frames > 1) {
    std::printf("  all steps: update %.3f s, full %.3f s, ratio x%.2f\n", updateTotal, fullTotal,
                fullTotal / updateTotal);
    std::printf("  median processor time: update %.4f s, full %.4f s, ratio x%.2f\n",
                median(updateCpu), median(fullCpu), median(fullCpu) / median(updateCpu));
  }
}

// Moves the live scene to `frame` and updates the engine: the processor time it took.
double updateTo(DynamicScene& live, DiscontinuityMeshEngine& engine, int frame) {
  const SceneChange change = live.changeToFrame(frame);
  const double cpu = cpuSeconds();
  live.apply(change);
  engine.update(live, change);
  return cpuSeconds() - cpu;
}

// A generated room (seed 1), loaded as the CLI loads a file: the loader reads scenes from paths.
Scene generatedRoom(int polygons, int frames) {
  SceneGeneratorOptions generator;
  generator.targetPolygons = polygons;
  generator.frames = frames;
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "penumbra-dm-update-bench.json";
  std::ofstream(path) << generateSceneJson(generator);
  Scene scene = loadScene(path.string());
  std::filesystem::remove(path);
  return scene;
}

// The median update step's processor time in a generated room of `polygons` polygons.
double scaleStep(int polygons) {
  const Scene scene = generatedRoom(polygons, 4);
  DynamicScene live(scene, 0);
  DiscontinuityMeshEngine engine;
  const double cpu = cpuSeconds();
  engine.build(live);
  std::printf(
      "generated %d-polygon room: built in %.1f s (processor), %lld faces on %d receivers\n",
      polygons, cpuSeconds() - cpu, engine.stats().meshFaces, scene.polygonCount());
  std::vector<double> steps;
  for (int frame = 1; frame < scene.frames; ++frame) {
    steps.push_back(updateTo(live, engine, frame));
    const DmStats s = engine.stats();
    std::printf(
        "  frame %d: update %.3f s; %lld meshes edited or built anew, %lld kept (%lld of them "
        "with their inputs carried over unassembled), %lld faces recomputed; stages s: surfaces "
        "%.3f casting %.3f EEE %.3f meshing %.3f backprojections %.3f verification %.3f\n",
        frame, steps.back(), s.editedMeshes + s.rebuiltMeshes, s.keptMeshes, s.carriedInputs,
        s.recomputedFaces, s.secondsSurfaces, s.secondsCasting, s.secondsEee, s.secondsMeshing,
        s.secondsBackprojections, s.secondsVerification);
  }
  std::printf("  median update step %.3f s\n", median(steps));
  return median(steps);
}

// `steps` frame steps of `scene` by update alone, walking the frames forth and back.
void updateSteps(const std::string& name, int steps) {
  const Scene scene = loadScene(name);
  if (scene.frames < 2) throw std::invalid_argument(name + ": --steps needs a moving scene");
  DynamicScene live(scene, 0);
  DiscontinuityMeshEngine engine;
  engine.build(live);
  std::vector<double> step, meshing, eee, verification, other;
  int frame = 0, direction = 1;
  for (int i = 0; i < steps; ++i) {
    if (frame + direction < 0 || frame + direction >= scene.frames) direction = -direction;
    frame += direction;
    step.push_back(updateTo(live, engine, frame));
    const DmStats s = engine.stats();
    meshing.push_back(s.secondsMeshing);
    eee.push_back(s.secondsEee);
    verification.push_back(s.secondsVerification);
    other.push_back(s.secondsSurfaces + s.secondsCasting + s.secondsBackprojections);
  }
  std::printf(
      "%s: %d update steps, median processor time %.4f s; median stages s: meshing %.4f EEE "
      "%.4f verification %.4f surfaces+casting+backprojections %.4f\n",
      name.c_str(), steps, median(step), median(meshing), median(eee), median(verification),
      median(other));
}

int run(int argc, char** argv) {
  const std::string root = PENUMBRA_SOURCE_DIR;
  if (argc == 4 && std::string(argv[1]) == "--steps") {
    char* end = nullptr;
    const long steps = std::strtol(argv[2], &end, 10);
    if (*end != '\0' || steps < 1 || steps > 1'000'000)
      throw std::invalid_argument(std::string("--steps: '") + argv[2] +
                                  "' is not a step count from 1 to 1,000,000");
    updateSteps(argv[3], int(steps));
    return 0;
  }
  if (argc > 1 && std::string(argv[1]) == "--scale") {
    std::vector<int> sizes{1000, 10000};
    if (argc > 2) {
      sizes.clear();
      std::stringstream list(argv[2]);
      for (std::string item; std::getline(list, item, ',');) {
        char* end = nullptr;
        const long polygons = std::strtol(item.c_str(), &end, 10);
        if (item.empty() || *end != '\0' || polygons < 50 || polygons > 10'000'000)
          throw std::invalid_argument("--scale: '" + item +
                                      "' is not a polygon count from 50 to 10,000,000");
        sizes.push_back(int(polygons));
      }
    }
    std::vector<double> steps;
    for (int polygons : sizes) steps.push_back(scaleStep(polygons));
    for (size_t i = 1; i < sizes.size(); ++i)
      std::printf("%d -> %d polygons: the median update step grows x%.1f\n", sizes[0], sizes[i],
                  steps[i] / steps[0]);
    return 0;
  }
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) scenes.push_back(argv[i]);
  const bool defaults = scenes.empty();
  if (defaults)
    scenes = {root + "/scenes/office-desk/desk-145.json",
              root + "/scenes/office-desk/desk-475.json",
              root + "/scenes/chair-room/chair-room.json"};
  for (const std::string& path : scenes) benchScene(path, loadScene(path));
  if (defaults) benchScene("generated 1k room", generatedRoom(1000, 5));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dm_update_bench: %s\n", e.what());
    return 1;
  }
}
