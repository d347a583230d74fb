// Hierarchical radiosity figures for the bundled scenes, on one core: links (total, passive),
// elements, leaves, shafts, memory per structure and seconds, as in Drettakis & Sillion 1997,
// Table 1 (31,130 links / 81 s for 227 polygons; 43,679 links / 130 s for 1,339 polygons on a
// 195 MHz R10000).
//
// Usage: radiosity_bench [--tolerance T] [--furnace] [scene.json ...]
// (default: the Cornell box and both chair rooms at tolerances 1e-3 and 3e-4).

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/scene/scene_loader.h"

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
      "%-22s %6d %8.0e %9lld %9lld %9lld %8lld %8lld %9lld %7.2f %7.2f %7.2f %7.2f %7.2f %8.3f "
      "%7.3f %7.3f %6.4f\n",
      path.substr(path.find_last_of('/') + 1).c_str(), scene.polygonCount(), tolerance, s.links,
      s.activeLinks, s.passiveLinks, s.elements, s.leaves, s.shafts, mib(s.elementBytes),
      mib(s.activeLinkBytes), mib(s.passiveLinkBytes), mib(s.shaftBytes), mib(s.totalBytes()),
      s.totalSeconds, s.refineSeconds, s.solveSeconds, absorbed.average() / emitted.average());
  if (furnace) {
    double low = 1e300, high = -1e300;
    for (const Element& e : solver.elements())
      if (e.isLeaf()) {
        const double irradiance =
            (e.radiometry.irradianceDirect + e.radiometry.irradianceIndirect).average();
        low = std::min(low, irradiance);
        high = std::max(high, irradiance);
      }
    std::printf("  furnace: leaf irradiance in [%.5f, %.5f], expected 2\n", low, high);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> tolerances;
  std::vector<std::string> scenes;
  bool furnace = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--tolerance" && i + 1 < argc)
      tolerances.push_back(std::atof(argv[++i]));
    else if (arg == "--furnace")
      furnace = true;
    else
      scenes.push_back(arg);
  }
  if (tolerances.empty()) tolerances = {1e-3, 3e-4};
  if (scenes.empty())
    for (const char* s :
         {"/scenes/cornell-box/cornell-box.json", "/scenes/chair-room/chair-room.json",
          "/scenes/chair-room/furnished-room.json"})
      scenes.push_back(std::string(PENUMBRA_SOURCE_DIR) + s);
  std::printf("%-22s %6s %8s %9s %9s %9s %8s %8s %9s %7s %7s %7s %7s %7s %8s %7s %7s %6s\n",
              "scene", "polys", "tol", "links", "active", "passive", "elems", "leaves", "shafts",
              "elemMiB", "actMiB", "pasMiB", "shfMiB", "totMiB", "seconds", "refine", "solve",
              "abs/em");
  for (double tolerance : tolerances)
    for (const std::string& scene : scenes) run(scene, tolerance, furnace);
  return 0;
}
