// `penumbra render SCENE --method raytrace -o OUT.png`: images of a frame.

#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/render/exr_io.h"
#include "penumbra/render/gl_context.h"
#include "penumbra/render/mesh_renderer.h"
#include "penumbra/render/png_writer.h"
#include "penumbra/render/ray_traced_image.h"
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
  const auto x = size.find('x');
  const auto isNumber = [](const std::string& s) {
    return !s.empty() && s.size() <= 5 && s.find_first_not_of("0123456789") == std::string::npos;
  };
  if (x == std::string::npos || !isNumber(size.substr(0, x)) || !isNumber(size.substr(x + 1)))
    throw UsageError("--size must look like 640x480, got '" + size + "'");
  camera.width = std::stoi(size.substr(0, x));
  camera.height = std::stoi(size.substr(x + 1));
  if (camera.width < 1 || camera.height < 1 || camera.width > 16384 || camera.height > 16384)
    throw UsageError("--size must lie in 1x1 .. 16384x16384");
}

// The radiosity solution drawn as its per-vertex mesh: radiance L = B / π (Lambertian).
Image renderRadiosity(const PosedScene& posed, const Camera& camera, double tolerance) {
  RadiosityOptions radiosityOptions;
  radiosityOptions.tolerance = tolerance;
  RadiositySolver solver(radiosityOptions);
  solver.build(posed);
  const RadiosityMesh& solution = solver.mesh();
  ColoredMesh mesh;
  mesh.positions = solution.positions;
  mesh.indices = solution.indices;
  mesh.colors.reserve(solution.radiosity.size());
  for (const Rgb& b : solution.radiosity) mesh.colors.push_back(b / 3.14159265358979323846);
  const auto context = GlContext::createHeadless();
  MeshRenderer renderer;
  return renderer.render(mesh, camera, camera.width, camera.height);
}

}  // namespace

int runRender(const RenderOptions& options, const CommonOptions& common) {
  if (options.method != "raytrace" && options.method != "radiosity")
    throw UsageError("--method " + options.method +
                     " is not available in this build (available: raytrace, radiosity)");
  const Scene scene = loadScene(options.scene);
  if (options.frame < 0 || options.frame >= scene.frames)
    throw UsageError("--frame " + std::to_string(options.frame) +
                     " is outside the scene's frames 0.." + std::to_string(scene.frames - 1));
  const PosedScene posed = poseAt(scene, options.frame);
  Camera camera = cameraFor(scene, posed);
  if (!options.size.empty()) parseSize(options.size, camera);

  if (options.method == "radiosity") {
    const std::filesystem::path parent = std::filesystem::path(options.output).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    const Image radiance = renderRadiosity(posed, camera, options.tolerance);
    const ToneMapping toneMapping{options.exposure > 0 ? options.exposure : autoExposure(radiance)};
    writePng(radiance, toneMapping, options.output);
    if (!common.quiet)
      std::fprintf(stderr, "wrote %s (%dx%d, exposure %g)\n", options.output.c_str(), camera.width,
                   camera.height, toneMapping.exposure);
    return kOk;
  }

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

  for (const std::string& path : {options.output, options.exr}) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (!path.empty() && !parent.empty()) std::filesystem::create_directories(parent);
  }
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
