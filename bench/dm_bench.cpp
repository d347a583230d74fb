// The exact soft-shadow engine (discontinuity meshing with backprojections), on one core:
//  1. full computation time per stage and mesh size for the desk scenes and generated scenes
//     (Loscos & Drettakis 1997 report their scenes of 145-475 polygons; goal: desk-475 in <= 1 s),
//     with the memory of each structure; the backprojection stage from scratch vs propagated from
//     face to neighbouring face, side by side;
//  2. irradiance at every mesh vertex by the face's backprojection vs by the per-point exact
//     reference, side by side (time ratio and largest difference);
//  3. against Monte Carlo (Embree): the time a point costs to reach 1e-3 relative error in the
//     penumbra, from the measured error at a fixed sample count (error ∝ 1/√N).
//
// Usage: dm_bench [--quick] [--large]   (--large adds the generated 10k-polygon scene)

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench_main.h"
#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/lighting/monte_carlo_estimator.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_generator.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"
#include "penumbra_points.h"

using namespace penumbra;

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}
double kib(std::size_t bytes) {
  return double(bytes) / 1024;
}

struct VertexSample {
  PolygonId receiver;
  int face;
  Vec3 p;
};

// Every vertex of every face boundary (a mesh vertex once per face around it), faces that face
// verification left unresolved excepted (they answer by computing at the point).
std::vector<VertexSample> meshVertices(const DiscontinuityMeshEngine& engine) {
  std::vector<VertexSample> out;
  for (const WorldPolygon& polygon : engine.posedScene().polygons) {
    const ReceiverMesh* mesh = engine.meshOf(polygon.id);
    if (!mesh) continue;
    for (const MeshFace& face : mesh->faces())
      if (!engine.isAnsweredAtPoint(polygon.id, face.index))
        for (const Polygon3& cycle : mesh->faceBoundary(face.index))
          for (const Vec3& v : cycle) out.push_back({polygon.id, face.index, v});
  }
  return out;
}

void runScene(const std::string& name, const std::string& path, bool monteCarlo) {
  const Scene scene = loadScene(path);
  const PosedScene posed = poseAt(scene, 0);
  DiscontinuityMeshEngine engine;
  const auto start = Clock::now();
  engine.build(PosedScene(posed));
  const double total = secondsSince(start);
  const DmStats& s = engine.stats();
  std::printf(
      "%-14s %6d %7.3f | %5.3f %5.3f %5.3f %5.3f %5.3f %5.3f %5.3f | %6d %6d %6d %6d %6d | %8lld "
      "%7lld %7lld | %7lld %7lld %7lld %5lld | %7.1f %7.1f %8.1f %8.1f %7.1f\n",
      name.c_str(), scene.polygonCount(), total, s.secondsSurfaces, s.secondsCasting,
      s.secondsVisibility, s.secondsEee, s.secondsMeshing, s.secondsBackprojections,
      s.secondsVerification, s.surfacesEmitterVertex, s.surfacesEmitterEdge, s.surfacesNonEmitter,
      s.surfacesOccluderPlane + s.surfacesOccluderPlaneEdge + s.surfacesOccluderPlaneVertex +
          s.surfacesCoplanarEdges + s.surfacesParallelEdgeCrossing + s.surfacesCoplanarEdgeCrossing,
      s.surfacesEee + s.surfacesEeeOccluder, s.storedIntersections, s.eeeSegments,
      s.visibleSegments, s.meshVertices, s.meshEdges, s.meshFaces, s.unresolvedFaces,
      kib(s.gridBytes), kib(s.surfaceCellBytes), kib(s.intersectionBytes), kib(s.meshBytes),
      kib(s.backprojectionBytes));

  // Backprojections from scratch at every face vs propagated from face to neighbouring face
  // (DmOptions::propagateBackprojections), side by side: the other way is built once more.
  {
    DmOptions otherOptions;
    otherOptions.propagateBackprojections = !otherOptions.propagateBackprojections;
    DiscontinuityMeshEngine other(otherOptions);
    other.build(PosedScene(posed));
    const DmStats& o = other.stats();
    const DmStats& scratch = otherOptions.propagateBackprojections ? s : o;
    const DmStats& propagated = otherOptions.propagateBackprojections ? o : s;
    std::printf(
        "  backprojection stage: from scratch %.3f s, propagated %.3f s (%lld of %lld "
        "face-lights propagated, %lld sent back to scratch), ratio %.2f; verification %.3f s "
        "vs %.3f s; unresolved faces %lld vs %lld\n",
        scratch.secondsBackprojections, propagated.secondsBackprojections,
        propagated.propagatedBackprojections, propagated.meshFaces * propagated.lights,
        propagated.propagationFallbacks,
        scratch.secondsBackprojections / propagated.secondsBackprojections,
        scratch.secondsVerification, propagated.secondsVerification, scratch.unresolvedFaces,
        propagated.unresolvedFaces);
  }

  // Irradiance at the mesh vertices: backprojection vs reference.
  const std::vector<VertexSample> vertices = meshVertices(engine);
  const UniformGrid grid(posed);
  const ExactReference reference(posed, &grid);
  std::vector<double> byBackprojection(vertices.size()), byReference(vertices.size());
  auto t = Clock::now();
  for (size_t i = 0; i < vertices.size(); ++i)
    byBackprojection[i] =
        engine.faceIrradianceAt(vertices[i].receiver, vertices[i].face, vertices[i].p).r;
  const double backprojectionSeconds = secondsSince(t);
  t = Clock::now();
  for (size_t i = 0; i < vertices.size(); ++i)
    byReference[i] =
        reference
            .irradiance(vertices[i].p, posed.polygons[vertices[i].receiver].plane.normal,
                        vertices[i].receiver)
            .r;
  const double referenceSeconds = secondsSince(t);
  // A vertex on a contact line (D0) has a different value on each side; the reference gives one
  // of them, so such vertices are counted apart rather than hidden in a maximum.
  int differing = 0;
  for (size_t i = 0; i < vertices.size(); ++i)
    differing +=
        std::abs(byBackprojection[i] - byReference[i]) > 1e-9 * std::max(byReference[i], 1e-3) ? 1
                                                                                               : 0;
  std::printf(
      "  vertices of resolved faces %zu: backprojection %.2f us/vertex, reference %.2f us/vertex, "
      "ratio %.2f; "
      "%d differ by > 1e-9 (contact lines, slivers, missing events)\n",
      vertices.size(), 1e6 * backprojectionSeconds / double(vertices.size()),
      1e6 * referenceSeconds / double(vertices.size()), referenceSeconds / backprojectionSeconds,
      differing);
  if (!monteCarlo) return;

  // Monte Carlo at penumbra points (0 < E < unoccluded), vs the DM evaluation there.
  const std::vector<bench::PenumbraPoint> penumbra =
      bench::samplePenumbraPoints(posed, reference, 200, 11);
  const RayCaster rays(posed);
  const MonteCarloEstimator estimator(posed, rays);
  const MonteCarloOptions options{1024, 4, 5};  // 4096 rays per light per point
  double squaredError = 0, dmSeconds = 0, mcSeconds = 0;
  for (const auto& [q, exact] : penumbra) {
    t = Clock::now();
    engine.irradiance(q.p, q.n);
    dmSeconds += secondsSince(t);
    t = Clock::now();
    const double estimate = estimator.irradiance(q.p, q.n, options).mean.r;
    mcSeconds += secondsSince(t);
    squaredError += std::pow((estimate - exact) / exact, 2);
  }
  const double rms = std::sqrt(squaredError / double(penumbra.size()));
  const double raysFor1e3 = 4096 * std::pow(rms / 1e-3, 2);
  const double mcSecondsFor1e3 = mcSeconds / double(penumbra.size()) * raysFor1e3 / 4096;
  std::printf(
      "  penumbra points %zu: Monte Carlo 4096 rays rms relative error %.2e -> %.0f rays "
      "for 1e-3, %.1f us/point; dm %.2f us/point (exact); ratio %.0f\n",
      penumbra.size(), rms, raysFor1e3, 1e6 * mcSecondsFor1e3,
      1e6 * dmSeconds / double(penumbra.size()),
      mcSecondsFor1e3 / (dmSeconds / double(penumbra.size())));
}

}  // namespace

static int benchMain(int argc, char** argv) {
  bool quick = false, large = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    if (!std::strcmp(argv[i], "--large")) large = true;
  }
  const std::string root = PENUMBRA_SOURCE_DIR;
  std::vector<std::pair<std::string, std::string>> scenes = {
      {"desk-145", root + "/scenes/office-desk/desk-145.json"}};
  if (!quick) {
    scenes.push_back({"desk-307", root + "/scenes/office-desk/desk-307.json"});
    scenes.push_back({"desk-475", root + "/scenes/office-desk/desk-475.json"});
  }
  const auto tmp = std::filesystem::temp_directory_path() / "penumbra-bench";
  std::filesystem::create_directories(tmp);
  std::vector<int> generated;
  if (!quick) generated.push_back(1000);
  if (large) generated.push_back(10000);
  for (int n : generated) {
    const auto path = tmp / ("generated-" + std::to_string(n) + ".json");
    std::ofstream(path) << generateSceneJson({n, 1, 4});
    scenes.push_back({"generated-" + std::to_string(n), path.string()});
  }
  std::printf(
      "# Full discontinuity mesh, one core. Seconds per stage: surfaces, casting, visibility, "
      "EEE tracing, meshing, backprojections, face verification. Surfaces: EV light-vertex, EV "
      "light-edge, non-emitter EV, occluder-plane, EEE. Then stored intersections, EEE polyline "
      "segments, visible EV segments; mesh vertices, edges, faces and unresolved faces. Memory "
      "in KiB: grid lists, per-surface cell lists, stored intersections, meshes, "
      "backprojections.\n");
  std::printf("%-14s %6s %7s | %41s | %34s | %24s | %29s | %s\n", "scene", "polys", "total s",
              "stages s", "surfaces", "inters. eee-segs visible", "mesh v/e/f unresolved",
              "memory KiB");
  for (const auto& [name, path] : scenes) runScene(name, path, name == "desk-475" || quick);
  return 0;
}

int main(int argc, char** argv) {
  return penumbra::bench::runReportingErrors("dm_bench", argc, argv, benchMain);
}
