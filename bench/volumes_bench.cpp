// Shadow-volume engine benchmark (plain main, prints a table): per-frame volume update,
// incremental vs rebuild (ratio), light jitter incremental vs rebuild, and frame time at 1024x768
// on the headless GL context (llvmpipe where there is no GPU), for desk-475 and a generated
// scene of about 100k triangles.
//
// Usage: volumes_bench [SOURCE_DIR]  (defaults to the source tree this was built from)

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "bench_main.h"
#include "penumbra/geometry/triangulation.h"
#include "penumbra/render/gl_context.h"
#include "penumbra/render/shadow_volume_renderer.h"
#include "penumbra/scene/scene_generator.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/volumes/light_samples.h"
#include "penumbra/volumes/shadow_volume_engine.h"

namespace {

using namespace penumbra;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Rebuilding every volume from the (already built) adjacency: what an engine without the
// incremental rules does each frame.
double rebuildAllMs(const Scene& scene, const std::vector<OccluderMesh>& meshes,
                    const ShadowVolumeEngine& engine, double frame) {
  const auto start = Clock::now();
  const std::vector<int> offsets = scene.objectPolygonOffsets();
  std::size_t sink = 0;
  for (const LightVolumes& light : engine.lights()) {
    for (int o = 0; o < int(scene.objects.size()); ++o) {
      const Transform t = scene.objects[o].transformAt(frame);
      std::vector<Vec3> near;
      near.reserve(meshes[o].vertices.size());
      for (const Vec3& v : meshes[o].vertices) near.push_back(t.applyToPoint(v));
      const int excluded = light.objectIndex == o ? light.polygon - offsets[o] : -1;
      sink += buildObjectVolume(meshes[o], std::move(near), light.position, 0, excluded)
                  .silhouetteEdges.size();
    }
  }
  if (sink == std::size_t(-1)) std::puts("");
  return msSince(start);
}

void benchScene(const std::string& name, const Scene& scene) {
  int triangles = 0;
  for (const SceneObject& object : scene.objects)
    for (const Polygon3& polygon : object.polygons) triangles += int(triangulate(polygon).size());
  std::vector<OccluderMesh> meshes;
  for (const SceneObject& object : scene.objects)
    meshes.push_back(buildOccluderMesh(object.polygons));

  ShadowVolumeEngine engine;
  auto start = Clock::now();
  engine.build(scene, 0);
  const double buildMs = msSince(start);
  std::printf("\n%s: %d polygons, %d triangles, %d objects, %zu lights; build %.2f ms\n",
              name.c_str(), scene.polygonCount(), triangles, int(scene.objects.size()),
              engine.lights().size(), buildMs);
  std::printf("  frame  incremental_ms  rebuild_ms  ratio  moved  rebuilt  linear  sil_edges\n");
  for (int f = 1; f < scene.frames; ++f) {
    start = Clock::now();
    engine.update(scene, f);
    const double inc = msSince(start);
    const double full = rebuildAllMs(scene, meshes, engine, f);
    const VolumeUpdateStats& s = engine.stats().frames.back();
    std::printf("  %5d  %14.3f  %10.3f  %5.1f  %5d  %7d  %6d  %9lld\n", f, inc, full, full / inc,
                s.occluderMoves + s.lightMoves, s.rebuilds, s.linearMoves, s.silhouetteEdges);
  }

  // Light jitter: 16 stratified samples of each light, incremental vs rebuild per sample.
  double jitterMs = 0, jitterRebuildMs = 0;
  const long long rebuildsBefore = engine.stats().jitterRebuilds;
  const long long incrementalBefore = engine.stats().jitterIncremental;
  for (int l = 0; l < int(engine.lights().size()); ++l) {
    const auto samples = stratifiedLightSamples(engine.lights()[l].worldPolygon, 16);
    for (const Vec3& sample : samples) {
      start = Clock::now();
      engine.moveLight(l, sample);
      jitterMs += msSince(start);
      jitterRebuildMs +=
          rebuildAllMs(scene, meshes, engine, scene.frames - 1) / double(engine.lights().size());
    }
    engine.moveLight(l, centroid(engine.lights()[l].worldPolygon));
  }
  std::printf(
      "  jitter (16 samples/light): incremental %.3f ms, rebuild %.3f ms, ratio %.1f; "
      "%lld object volumes moved by one vector, %lld rebuilt\n",
      jitterMs, jitterRebuildMs, jitterRebuildMs / jitterMs,
      engine.stats().jitterIncremental - incrementalBefore,
      engine.stats().jitterRebuilds - rebuildsBefore);

  // Frame time at 1024x768.
  const PosedScene posed = poseAt(scene, scene.frames - 1);
  ShadowVolumeRenderer renderer;
  const Camera camera = scene.camera.value_or(Camera{});
  for (int n : {1, 4, 16}) {
    ShadowVolumeRenderOptions options;
    options.lightSamples = n;
    renderer.render(posed, engine, camera, 1024, 768, options);  // warm-up
    const int repeats = n == 1 ? 3 : 1;
    start = Clock::now();
    for (int i = 0; i < repeats; ++i) renderer.render(posed, engine, camera, 1024, 768, options);
    std::printf("  1024x768, %2d light samples: %.1f ms/frame\n", n, msSince(start) / repeats);
  }
}

}  // namespace

static int benchMain(int argc, char** argv) {
  const std::string source = argc > 1 ? argv[1] : PENUMBRA_SOURCE_DIR;
  const auto context = GlContext::createHeadless();
  std::printf("GL: %s (%s)\n", context->versionString().c_str(), context->rendererString().c_str());
  benchScene("desk-475", loadScene(source + "/scenes/office-desk/desk-475.json"));

  SceneGeneratorOptions generator;
  generator.targetPolygons = 50000;  // quads: about 100k triangles
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "penumbra-volumes-bench-100k.json";
  std::ofstream(path) << generateSceneJson(generator);
  benchScene("generated-100k-triangles", loadScene(path.string()));
  std::filesystem::remove(path);
  return 0;
}

int main(int argc, char** argv) {
  return penumbra::bench::runReportingErrors("volumes_bench", argc, argv, benchMain);
}
