// Hierarchical radiosity figures for the bundled scenes, on one core: links (total, passive),
// elements, leaves, shafts, memory per structure and seconds, as in Drettakis & Sillion 1997,
// Table 1 (31,130 links / 81 s for 227 polygons; 43,679 links / 130 s for 1,339 polygons on a
// 195 MHz R10000).
//
// Usage: radiosity_bench [--tolerance T] [--furnace] [--convergence] [scene.json ...]
// (default: the Cornell box and both chair rooms at tolerances 1e-3 and 3e-4).
// --furnace: every material emits 1 with reflectance 0.5: the area mean of the irradiance must be
//   2, absorbed = emitted.
// --convergence: the direct part at the element vertices of the first scene against the exact
//   reference irradiance, per tolerance: links, mean and largest error (relative to the mean
//   exact irradiance), seconds.

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "penumbra/lighting/exact_reference.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/uniform_grid.h"

using namespace penumbra;

namespace {

void run(const std::string& path, double tolerance, bool furnace) {
  Scene scene = loadScene(path);
  if (furnace)
    for (Material& m : scene.materials) {
      m.emission = Rgb::gray(1);
      m.reflectance = Rgb::gray(0.5);
    }
  RadiosityOptions options;
  options.tolerance = tolerance;
  RadiositySolver solver(options);
  solver.build(scene, 0);
  const RadiosityStats& s = solver.stats();
  const Rgb emitted = solver.emittedPower(), absorbed = solver.absorbedPower();
  const auto mib = [](std::size_t bytes) { return double(bytes) / (1 << 20); };
  std::printf(
      "%-22s %6d %8.0e %9lld %9lld %9lld %8lld %8lld %9lld %9lld %7.2f %7.2f %7.2f %7.2f %7.2f "
      "%8.3f "
      "%7.3f %7.3f %6.4f\n",
      path.substr(path.find_last_of('/') + 1).c_str(), scene.polygonCount(), tolerance, s.links,
      s.activeLinks, s.passiveLinks, s.elements, s.leaves, s.shafts, s.polygonShafts,
      mib(s.elementBytes), mib(s.activeLinkBytes), mib(s.passiveLinkBytes), mib(s.shaftBytes),
      mib(s.totalBytes()), s.totalSeconds, s.refineSeconds, s.solveSeconds,
      absorbed.average() / emitted.average());
  if (furnace) {
    double low = 1e300, high = -1e300, sum = 0, area = 0, within = 0;
    for (const Element& e : solver.elements())
      if (e.isLeaf()) {
        const double irradiance =
            (e.radiometry.irradianceDirect + e.radiometry.irradianceIndirect).average();
        low = std::min(low, irradiance);
        high = std::max(high, irradiance);
        sum += irradiance * e.area;
        area += e.area;
        if (std::abs(irradiance - 2) <= 0.02) within += e.area;
      }
    std::printf(
        "  furnace: area mean of E %.5f (expected 2, error %.3f%%), absorbed/emitted %.5f, leaf E "
        "in [%.3f, %.3f], area within 1%%: %.1f%%\n",
        sum / area, 100 * std::abs(sum / area - 2) / 2, absorbed.average() / emitted.average(), low,
        high, 100 * within / area);
  }
}

void convergence(const std::string& path, const std::vector<double>& tolerances) {
  const Scene scene = loadScene(path);
  const PosedScene posed = poseAt(scene, 0);
  const UniformGrid grid(posed);
  const ExactReference reference(posed, &grid);
  std::printf("direct part vs exact reference at element vertices: %s\n", path.c_str());
  std::printf("%9s %9s %9s %16s %15s %15s %9s\n", "tolerance", "links", "vertices",
              "mean|err|/meanE", "p95|err|/meanE", "max|err|/meanE", "seconds");
  for (double tolerance : tolerances) {
    RadiosityOptions options;
    options.tolerance = tolerance;
    RadiositySolver solver(options);
    const auto start = std::chrono::steady_clock::now();
    solver.build(posed);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const RadiosityMesh& mesh = solver.mesh();
    const size_t stride = std::max<size_t>(1, mesh.positions.size() / 1000);
    std::vector<double> errors;
    double exactSum = 0, errorSum = 0;
    for (size_t v = 0; v < mesh.positions.size(); v += stride) {
      if (posed.polygons[mesh.polygons[v]].isLight) continue;
      const double exact =
          reference.irradiance(mesh.positions[v], mesh.normals[v], mesh.polygons[v]).average();
      errors.push_back(std::abs(mesh.directIrradiance[v].average() - exact));
      errorSum += errors.back();
      exactSum += exact;
    }
    std::sort(errors.begin(), errors.end());
    const double meanExact = exactSum / double(errors.size());
    std::printf("%9.0e %9lld %9zu %16.4f %15.4f %15.4f %9.3f\n", tolerance, solver.stats().links,
                mesh.positions.size(), errorSum / exactSum,
                errors[errors.size() * 95 / 100] / meanExact, errors.back() / meanExact, seconds);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> tolerances;
  std::vector<std::string> scenes;
  bool furnace = false, convergenceTable = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--tolerance" && i + 1 < argc)
      tolerances.push_back(std::atof(argv[++i]));
    else if (arg == "--furnace")
      furnace = true;
    else if (arg == "--convergence")
      convergenceTable = true;
    else
      scenes.push_back(arg);
  }
  if (convergenceTable) {
    if (tolerances.empty()) tolerances = {1e-2, 3e-3, 1e-3, 3e-4, 1e-4};
    convergence(scenes.empty()
                    ? std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.json"
                    : scenes.front(),
                tolerances);
    return 0;
  }
  if (tolerances.empty()) tolerances = {1e-3, 3e-4};
  if (scenes.empty())
    for (const char* s :
         {"/scenes/cornell-box/cornell-box.json", "/scenes/chair-room/chair-room.json",
          "/scenes/chair-room/furnished-room.json"})
      scenes.push_back(std::string(PENUMBRA_SOURCE_DIR) + s);
  std::printf("%-22s %6s %8s %9s %9s %9s %8s %8s %9s %9s %7s %7s %7s %7s %7s %8s %7s %7s %6s\n",
              "scene", "polys", "tol", "links", "active", "passive", "elems", "leaves", "shafts",
              "polyShf", "elemMiB", "actMiB", "pasMiB", "shfMiB", "totMiB", "seconds", "refine",
              "solve", "abs/em");
  for (double tolerance : tolerances)
    for (const std::string& scene : scenes) run(scene, tolerance, furnace);
  return 0;
}
