// `penumbra render SCENE --method raytrace -o OUT.png`: images of a frame.

#include <cstdio>
#include <filesystem>
#include <regex>

#include "commands.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/render/exr_io.h"
#include "penumbra/render/gl_context.h"
#include "penumbra/render/png_writer.h"
#include "penumbra/render/ray_traced_image.h"
#include "penumbra/render/shadow_volume_renderer.h"
#include "penumbra/render/tone_mapping.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"
#include "progress.h"

namespace penumbra::cli {

namespace {

// The scene's camera, or one looking at the scene's box from the front (+z) when it has none.
Camera cameraFor(const Scene& scene, const PosedScene& posed) {
  if (scene.camera) return *scene.camera;
  Camera c;
  const Vec3 center = posed.bounds.center();
  const double radius = posed.bounds.diagonalLength() / 2;
  c.target = center;
  c.eye = center + Vec3{0, 0, radius / std::tan(c.fovYDegrees * 3.14159265358979 / 360) * 1.1};
  return c;
}

void parseSize(const std::string& size, Camera& camera) {
  static const std::regex pattern(R"((\d{1,5})x(\d{1,5}))");
  std::smatch m;
  if (!std::regex_match(size, m, pattern))
    throw UsageError("--size must look like 640x480, got '" + size + "'");
  camera.width = std::stoi(m[1]);
  camera.height = std::stoi(m[2]);
  if (camera.width < 1 || camera.height < 1 || camera.width > 16384 || camera.height > 16384)
    throw UsageError("--size must lie in 1x1 .. 16384x16384");
}

void createParentFolders(const RenderOptions& options) {
  for (const std::string& path : {options.output, options.exr}) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (!path.empty() && !parent.empty()) std::filesystem::create_directories(parent);
  }
}

// Shadow volumes: built at frame 0 and updated incrementally to the requested frame.
int renderVolumes(const RenderOptions& options, const CommonOptions& common, const Scene& scene,
                  const PosedScene& posed, const Camera& camera) {
  const auto context = GlContext::createHeadless();
  ShadowVolumeEngine engine;
  engine.build(scene, 0);
  for (int f = 1; f <= options.frame; ++f) engine.update(scene, f);
  ShadowVolumeRenderer renderer;
  ShadowVolumeRenderOptions so;
  so.lightSamples = options.lightSamples;
  const Image radiance = renderer.render(posed, engine, camera, camera.width, camera.height, so);
  createParentFolders(options);
  const ToneMapping toneMapping{options.exposure > 0 ? options.exposure : autoExposure(radiance)};
  writePng(radiance, toneMapping, options.output);
  if (!options.exr.empty()) {
    so.output = ShadowVolumeRenderOptions::Output::kIrradiance;
    writeExr(renderer.render(posed, engine, camera, camera.width, camera.height, so), options.exr);
  }
  if (!common.quiet) {
    const VolumeUpdateStats& s = engine.stats().frames.back();
    std::fprintf(stderr,
                 "wrote %s (%dx%d, exposure %g; volumes: %d light x object, %lld silhouette "
                 "edges, %lld jitter moves incremental, %lld rebuilt)\n",
                 options.output.c_str(), camera.width, camera.height, toneMapping.exposure,
                 s.volumes, s.silhouetteEdges, engine.stats().jitterIncremental,
                 engine.stats().jitterRebuilds);
  }
  return kOk;
}

}  // namespace

int runRender(const RenderOptions& options, const CommonOptions& common) {
  if (options.method != "raytrace" && options.method != "volumes")
    throw UsageError("--method " + options.method +
                     " is not available in this build (available: raytrace, volumes)");
  const Scene scene = loadScene(options.scene);
  if (options.frame < 0 || options.frame >= scene.frames)
    throw UsageError("--frame " + std::to_string(options.frame) +
                     " is outside the scene's frames 0.." + std::to_string(scene.frames - 1));
  const PosedScene posed = poseAt(scene, options.frame);
  Camera camera = cameraFor(scene, posed);
  if (!options.size.empty()) parseSize(options.size, camera);
  if (options.method == "volumes") return renderVolumes(options, common, scene, posed, camera);

  const UniformGrid grid(posed);
  const ExactReference reference(posed, &grid);
  const RayCaster rays(posed);
  Progress progress("render (raytrace)", camera.height, common.quiet);
  RayTraceOptions rt;
  rt.width = camera.width;
  rt.height = camera.height;
  rt.samplesPerPixel = options.samplesPerPixel;
  rt.threads = common.threads;
  rt.onRowDone = [&](long long rows) { progress.advance(rows); };
  const RayTracedImage image = renderRayTraced(posed, camera, rays, reference, rt);

  createParentFolders(options);
  const ToneMapping toneMapping{options.exposure > 0 ? options.exposure
                                                     : autoExposure(image.radiance)};
  writePng(image.radiance, toneMapping, options.output);
  if (!options.exr.empty()) writeExr(image.irradiance, options.exr);
  if (!common.quiet)
    std::fprintf(stderr, "wrote %s (%dx%d, exposure %g)%s%s\n", options.output.c_str(),
                 camera.width, camera.height, toneMapping.exposure,
                 options.exr.empty() ? "" : ", irradiance in ", options.exr.c_str());
  return kOk;
}

}  // namespace penumbra::cli
