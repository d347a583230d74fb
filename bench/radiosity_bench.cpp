// Hierarchical radiosity figures for the bundled scenes, on one core: links (total, passive),
// elements, leaves, shafts, memory per structure and seconds, as in Drettakis & Sillion 1997,
// Table 1 (31,130 links / 81 s for 227 polygons; 43,679 links / 130 s for 1,339 polygons on a
// 195 MHz R10000).
//
// Usage: radiosity_bench [--tolerance T] [--furnace] [--convergence] [--element-shares]
//                        [--exact-visibility] [--exact-gather-contrast C] [scene.json ...]
// (default: the Cornell box and both chair rooms at tolerances 1e-3 and 3e-4).
// --furnace: every material emits 1 with reflectance 0.5, the lamps left out: the irradiance must
//   be 2 everywhere, absorbed = emitted.
// --element-shares: RadiosityOptions::elementSourceShares (element sources send per cell).
// --exact-visibility: RadiosityOptions::exactVisibility (element links' visibility computed
//   exactly at 16 receiver points instead of by 16 rays).
// --exact-gather-contrast C: RadiosityOptions::exactGatherContrast (partly hidden element
//   sources brighter than C x the mean radiosity are gathered exactly by the final solution).
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
#include <cstdint>
#include <limits>

#include "bench_main.h"
#include "penumbra/geometry/cosine_direction.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"

using namespace penumbra;

namespace {

void run(const std::string& path, double tolerance, bool furnace, bool elementShares,
         bool exactVisibility, double exactGatherContrast) {
  Scene scene = loadScene(path);
  // The furnace leaves out the lamps (objects named "light"): single polygons 1 cm below the
  // ceiling, whose dark backs the ceiling sees, where E < M/(1−ρ) in the exact solution too.
  if (furnace) std::erase_if(scene.objects, [](const SceneObject& o) { return o.name == "light"; });
  if (furnace)
    for (Material& m : scene.materials) {
      m.emission = Rgb::gray(1);
      m.reflectance = Rgb::gray(0.5);
    }
  RadiosityOptions options;
  options.tolerance = tolerance;
  options.elementSourceShares = elementShares;
  options.exactVisibility = exactVisibility;
  options.exactGatherContrast = exactGatherContrast;
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
  std::printf(
      "  final gather %.3f s: %lld rays, %lld met a back face or nothing; %d Jacobi iterations\n",
      s.finalGatherSeconds, s.finalGatherRays, s.finalGatherMisses, s.finalIterations);
  if (furnace) {
    // M/(1−ρ) holds only where every direction meets the front of a polygon. Near a one-sided
    // lamp 1 cm below the ceiling the ceiling sees the lamp's back, which has no radiosity in the
    // model (nor in the exact solution), so such leaves are counted apart: a leaf sees back faces
    // when one of 256 cosine-distributed rays from 16 of its points meets a polygon from behind.
    const PosedScene posed = poseAt(scene, 0);
    const RayCaster rays(posed);
    std::uint32_t state = 12345;
    const auto uniform = [&] {
      state = state * 1664525u + 1013904223u;
      return double(state >> 8) / double(1 << 24);
    };
    const auto seesBackFaces = [&](const Element& e) {
      for (int point = 0; point < 16; ++point) {
        const Vec3 x = e.samplePoint((point % 4 + uniform()) / 4, (point / 4 + uniform()) / 4);
        for (int ray = 0; ray < 16; ++ray) {
          const double a = uniform(), turn = uniform();
          const Vec3 d = cosineDirection(e.normal, a, turn);
          const auto hit = rays.intersect(x, d, 0, std::numeric_limits<double>::infinity(),
                                          PolygonId(e.polygon));
          if (hit && dot(posed.polygons[hit->polygon].plane.normal, d) > 0) return true;
        }
      }
      return false;
    };
    // Leaves that see back faces are counted once, for both measures below.
    std::vector<char> back(solver.elements().size(), 0);
    for (size_t i = 0; i < back.size(); ++i)
      if (solver.elements()[i].isLeaf()) back[i] = seesBackFaces(solver.elements()[i]) ? 1 : 0;
    // The solution's leaf irradiance (the mean pushed down from the links above) and what is
    // shown (the final gather's, see RadiosityOptions::finalGather), side by side.
    const auto report = [&](const char* what, Rgb NodeRadiometry::*direct,
                            Rgb NodeRadiometry::*indirect) {
      double low = 1e300, high = -1e300, sum = 0, area = 0, within = 0, backArea = 0,
             frontWithin = 0;
      for (size_t i = 0; i < back.size(); ++i) {
        const Element& e = solver.elements()[i];
        if (!e.isLeaf()) continue;
        const double irradiance = (e.radiometry.*direct + e.radiometry.*indirect).average();
        low = std::min(low, irradiance);
        high = std::max(high, irradiance);
        sum += irradiance * e.area;
        area += e.area;
        const bool close = std::abs(irradiance - 2) <= 0.02;
        if (close) within += e.area;
        if (back[i])
          backArea += e.area;
        else if (close)
          frontWithin += e.area;
      }
      std::printf(
          "  furnace, %-11s area mean of E %.5f (error %.3f%%), leaf E in [%.3f, %.3f], area "
          "within 1%%: %.1f%%; %.2f%% of the area sees back faces, %.1f%% of the rest within 1%%\n",
          what, sum / area, 100 * std::abs(sum / area - 2) / 2, low, high, 100 * within / area,
          100 * backArea / area, 100 * frontWithin / (area - backArea));
    };
    std::printf("  furnace: expected E = 2; absorbed/emitted %.5f; final gather %.3f s\n",
                absorbed.average() / emitted.average(), s.finalGatherSeconds);
    report("solution:", &NodeRadiometry::irradianceDirect, &NodeRadiometry::irradianceIndirect);
    report("shown:", &NodeRadiometry::finalDirect, &NodeRadiometry::finalIndirect);
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

static int benchMain(int argc, char** argv) {
  std::vector<double> tolerances;
  std::vector<std::string> scenes;
  bool furnace = false, convergenceTable = false, elementShares = false, exactVisibility = false;
  double exactGatherContrast = RadiosityOptions{}.exactGatherContrast;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--tolerance" && i + 1 < argc)
      tolerances.push_back(std::atof(argv[++i]));
    else if (arg == "--furnace")
      furnace = true;
    else if (arg == "--element-shares")
      elementShares = true;
    else if (arg == "--exact-visibility")
      exactVisibility = true;
    else if (arg == "--exact-gather-contrast" && i + 1 < argc)
      exactGatherContrast = std::atof(argv[++i]);
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
    for (const std::string& scene : scenes)
      run(scene, tolerance, furnace, elementShares, exactVisibility, exactGatherContrast);
  return 0;
}

int main(int argc, char** argv) {
  return penumbra::bench::runReportingErrors("radiosity_bench", argc, argv, benchMain);
}
