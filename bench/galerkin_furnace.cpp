// The Galerkin core's furnace, leaf by leaf: every material emits M = 1 with reflectance 1/2 and
// the scene's emitters are left out, so that in a closed scene E = 2 at every point (B = M + ρE,
// and a uniform B gives E = B). Per tolerance: leaves, the worst, median and 99th-percentile leaf
// error |E − 2| / 2 (E the leaf's mean irradiance), how many leaves (and what share of the area)
// are off by more than 1%, absorbed/emitted and seconds (one core).
//
// --explain: for the worst leaf at the last tolerance, every link from an element source feeding
// the leaf or one of its ancestors: the link's share of the leaf's mean direct irradiance (its
// linear function restricted to the leaf), the exact mean visible point form factor of the source
// over the leaf (ExactReference, 24 x 24 points), and the exact L2 projection of that form factor
// onto the ancestor's linear basis (32 x 32 points) restricted to the leaf: an estimate equal to
// the projection but far from the exact mean is the linear basis's error, not the estimate's.
// Links from cluster sources are counted apart (not compared).
//
// Usage: galerkin_furnace [--tolerances a,b,...] [--room-only] [--explain] [scene.json ...]
// --room-only: only the objects whose names start with "room" (the empty room).
// (default: the chair room, empty, at 3e-3, 1e-3, 3e-4, 1e-4 and 3e-5, explained)

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_statistics.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/radiosity/galerkin/galerkin_radiosity.h"
#include "penumbra/scene/closedness.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/dynamic_scene.h"

using namespace penumbra;

namespace {

using Galerkin = GalerkinRadiosity;
using Clock = std::chrono::steady_clock;

// The furnace version of a scene: emitters left out, every material M = 1, ρ = 1/2.
Scene furnaceOf(Scene scene, bool roomOnly) {
  std::erase_if(scene.objects, [&](const SceneObject& object) {
    if (roomOnly && object.name.rfind("room", 0) != 0) return true;
    return std::any_of(object.polygonMaterial.begin(), object.polygonMaterial.end(),
                       [&](int m) { return scene.materials[size_t(m)].isEmitter(); });
  });
  for (Material& m : scene.materials) {
    m.emission = Rgb::gray(1);
    m.reflectance = Rgb::gray(0.5);
  }
  return scene;
}

Polygon3 loopOf(const ElementShape& shape) {
  Polygon3 loop;
  for (int i = 0; i < shape.vertexCount; ++i) loop.push_back(shape.vertices[size_t(i)]);
  return loop;
}

double leafIrradiance(const Galerkin::GElement& e) {
  return (e.node.irradianceDirect[0] + e.node.irradianceIndirect[0]).average();
}

bool isOpenLeaf(const Galerkin::GElement& e) {
  return e.isLeaf() && e.cover != Galerkin::GElement::kCovered;
}

// The links feeding `leaf` and its ancestors, compared as the header says.
void explain(const Galerkin& solver, const DynamicScene& live, int leaf) {
  const auto& elements = solver.elements();
  const Galerkin::GElement& at = elements[size_t(leaf)];
  const PosedScene& scene = live.posed();
  const ExactReference reference(scene, &live.grid());
  std::vector<PolygonId> everyPolygon;
  for (const WorldPolygon& p : scene.polygons) everyPolygon.push_back(p.id);
  // The visible form factor of an element's shape from x on the leaf's polygon.
  const auto formFactor = [&](const Vec3& x, const Vec3& n, const Galerkin::GElement& source) {
    const WorldPolygon& polygon = scene.polygons[source.polygon];
    return reference.visibleFormFactor(x, n, loopOf(source.shape), polygon.plane, polygon.id,
                                       everyPolygon, at.polygon);
  };
  const Vec3 centre = at.shape.centroid();
  const Vec3 normal = at.shape.normal;
  constexpr int kLeafPoints = 24, kProjectionPoints = 32;
  std::printf("  worst leaf %d (polygon %d, %.3g m^2 at %.3f %.3f %.3f): E %.4f, direct %.4f\n",
              leaf, at.polygon, at.area, centre.x, centre.y, centre.z, leafIrradiance(at),
              at.node.irradianceDirect[0].average());
  double estimated = 0, exact = 0, projected = 0;
  for (int e = leaf; e >= 0; e = elements[size_t(e)].parent) {
    const Galerkin::GElement& ancestor = elements[size_t(e)];
    const auto phi = ancestor.basis.at(centre);
    double levelEstimate = 0, levelExact = 0, levelProjection = 0;
    int fromClusters = 0, fromElements = 0;
    for (const Galerkin::GLink& link : solver.links()) {
      if (!link.active() || !link.receiver.isElement() || link.receiver.index != e) continue;
      if (link.source.isCluster()) {
        ++fromClusters;
        continue;
      }
      ++fromElements;
      const Galerkin::GElement& source = elements[size_t(link.source.index)];
      const double emission = source.node.emission.average();
      double estimate = 0;
      for (size_t beta = 0; beta < 3; ++beta) estimate += link.k[beta * 3] * phi[beta] * emission;
      double mean = 0;
      for (int i = 0; i < kLeafPoints; ++i)
        for (int j = 0; j < kLeafPoints; ++j)
          mean += formFactor(at.shape.samplePoint((i + 0.5) / kLeafPoints, (j + 0.5) / kLeafPoints),
                             normal, source);
      mean *= emission / (kLeafPoints * kLeafPoints);
      std::array<double, 3> coefficients{};
      for (int i = 0; i < kProjectionPoints; ++i)
        for (int j = 0; j < kProjectionPoints; ++j) {
          const Vec3 x = ancestor.shape.samplePoint((i + 0.5) / kProjectionPoints,
                                                    (j + 0.5) / kProjectionPoints);
          const double f = formFactor(x, ancestor.shape.normal, source);
          const auto basis = ancestor.basis.at(x);
          for (size_t b = 0; b < 3; ++b)
            coefficients[b] += f * basis[b] / (kProjectionPoints * kProjectionPoints);
        }
      double projection = 0;
      for (size_t b = 0; b < 3; ++b) projection += coefficients[b] * phi[b] * emission;
      levelEstimate += estimate;
      levelExact += mean;
      levelProjection += projection;
      if (std::abs(estimate - mean) > 0.01)
        std::printf(
            "      from element %d (polygon %d, %.3g m^2): estimate %.4f, L2 projection %.4f, "
            "exact "
            "%.4f (mean transfer %.4f, spread %.4f, hidden %.4f)\n",
            link.source.index, source.polygon, source.area, estimate, projection, mean,
            link.meanTransfer, link.spread, link.hiddenTransfer);
    }
    std::printf(
        "    ancestor %d (%.3g m^2): %d links from elements: estimate %.4f, L2 projection %.4f, "
        "exact %.4f; %d from clusters\n",
        e, ancestor.area, fromElements, levelEstimate, levelProjection, levelExact, fromClusters);
    estimated += levelEstimate;
    exact += levelExact;
    projected += levelProjection;
  }
  std::printf(
      "    all levels, links from elements: estimate %.4f, L2 projection %.4f, exact %.4f\n",
      estimated, projected, exact);
}

void furnace(const std::string& path, const std::vector<double>& tolerances, bool roomOnly,
             bool explainWorst) {
  const Scene scene = furnaceOf(loadScene(path), roomOnly);
  const DynamicScene live(scene, 0);
  std::printf("%s%s: %d polygons\n", path.c_str(), roomOnly ? " (room only)" : "",
              int(live.posed().polygons.size()));
  // E = 2 holds only where every direction meets a surface.
  const ClosednessReport closedness = checkClosedness(scene, live.posed());
  if (!closedness.isSceneClosed)
    std::printf("  (not closed: %d open edges, %.3g m; light escapes and E < 2 near them)\n",
                closedness.sceneOpenEdgeCount, closedness.sceneOpenEdgeLength);
  std::printf("  %-9s %7s %8s %8s %8s %14s %9s %8s\n", "tolerance", "leaves", "worst", "median",
              "p99", "over 1% (area)", "abs/emit", "seconds");
  for (size_t t = 0; t < tolerances.size(); ++t) {
    GalerkinOptions options;
    options.tolerance = tolerances[t];
    options.threads = 1;
    Galerkin solver(options);
    const auto start = Clock::now();
    solver.build(live);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    std::vector<double> errors;
    double area = 0, areaOff = 0, worst = -1;
    int over = 0, worstLeaf = -1;
    const auto& elements = solver.elements();
    for (size_t i = 0; i < elements.size(); ++i) {
      const Galerkin::GElement& e = elements[i];
      if (!isOpenLeaf(e)) continue;
      const double error = std::abs(leafIrradiance(e) - 2) / 2;
      errors.push_back(error);
      area += e.area;
      if (error > 0.01) {
        ++over;
        areaOff += e.area;
      }
      if (error > worst) {
        worst = error;
        worstLeaf = int(i);
      }
    }
    if (errors.empty()) {
      std::printf("  %-9g no open leaves\n", tolerances[t]);
      continue;
    }
    const double energy = solver.absorbedPower().average() / solver.emittedPower().average();
    std::printf("  %-9g %7zu %7.2f%% %7.2f%% %7.2f%% %6d (%5.1f%%) %9.4f %8.3f\n", tolerances[t],
                errors.size(), 100 * worst, 100 * bench::median(errors),
                100 * bench::percentile(errors, 0.99), over, 100 * areaOff / area, energy, seconds);
    if (explainWorst && t + 1 == tolerances.size() && worstLeaf >= 0)
      explain(solver, live, worstLeaf);
  }
}

int run(int argc, char** argv) {
  std::vector<double> tolerances;
  std::vector<std::string> scenes;
  bool roomOnly = false, explainWorst = false;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--tolerances" && i + 1 < argc) {
      std::stringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');) {
        char* end = nullptr;
        const double tolerance = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !(tolerance > 0))
          throw std::invalid_argument("--tolerances: '" + item + "' is not a positive number");
        tolerances.push_back(tolerance);
      }
    } else if (flag == "--tolerances") {
      throw std::invalid_argument("--tolerances needs a comma-separated list of tolerances");
    } else if (flag == "--room-only") {
      roomOnly = true;
    } else if (flag == "--explain") {
      explainWorst = true;
    } else {
      scenes.push_back(flag);
    }
  }
  if (scenes.empty()) {
    scenes = {std::string(PENUMBRA_SOURCE_DIR) + "/scenes/chair-room/chair-room.json"};
    roomOnly = true;
    explainWorst = true;
  }
  if (tolerances.empty()) tolerances = {3e-3, 1e-3, 3e-4, 1e-4, 3e-5};
  for (const std::string& path : scenes) furnace(path, tolerances, roomOnly, explainWorst);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "galerkin_furnace: %s\n", e.what());
    return 1;
  }
}
