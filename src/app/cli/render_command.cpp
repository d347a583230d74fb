// `penumbra render SCENE --method raytrace|dm|radiosity|galerkin|volumes -o OUT.png`: images of a
// frame, or with --frames A:B (dm) a strip of frames reached by updates.

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "frame_range.h"
#include "frame_walk.h"
#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/dm/irradiance_mesh.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/radiosity/combined_solution.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/render/exr_io.h"
#include "penumbra/render/gl_context.h"
#include "penumbra/render/mesh_renderer.h"
#include "penumbra/render/png_writer.h"
#include "penumbra/render/radiance_mesh.h"
#include "penumbra/render/ray_traced_image.h"
#include "penumbra/render/shadow_volume_renderer.h"
#include "penumbra/render/tone_mapping.h"
#include "penumbra/scene/scene_camera.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"
#include "penumbra/volumes/shadow_volume_engine.h"
#include "progress.h"

namespace penumbra::cli {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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

// Writes the tone-mapped PNG (and the raw irradiance EXR when asked), creating folders.
// `exposureFrom` (when given) sets the automatic exposure instead of `radiance`: the same picture
// without overlays, so that drawing the edges does not darken it.
void writeImages(const RenderOptions& options, const CommonOptions& common, const Image& radiance,
                 const Image* irradiance, const std::string& details,
                 const Image* exposureFrom = nullptr) {
  for (const std::string& path : {options.output, options.exr}) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (!path.empty() && !parent.empty()) std::filesystem::create_directories(parent);
  }
  const ToneMapping toneMapping{options.exposure > 0
                                    ? options.exposure
                                    : autoExposure(exposureFrom ? *exposureFrom : radiance)};
  // The EXR first: when it cannot be written, no PNG is left behind as if all went well.
  if (!options.exr.empty()) {
    if (!irradiance) throw UsageError("--exr is not available with --method " + options.method);
    writeExr(*irradiance, options.exr);
  }
  writePng(radiance, toneMapping, options.output);
  if (!common.quiet)
    std::fprintf(stderr, "wrote %s (%dx%d, exposure %g)%s%s%s\n", options.output.c_str(),
                 radiance.width, radiance.height, toneMapping.exposure,
                 options.exr.empty() ? "" : ", irradiance in ", options.exr.c_str(),
                 details.c_str());
}

// Every pixel's direct irradiance by the exact reference.
void renderRaytrace(const RenderOptions& options, const CommonOptions& common,
                    const DynamicScene& live, const Camera& camera) {
  const PosedScene& posed = live.posed();
  const ExactReference reference(posed, &live.grid());
  const RayCaster& rays = live.rays();
  Progress progress("render (raytrace)", camera.height, common.quiet);
  RayTraceOptions rt;
  rt.width = camera.width;
  rt.height = camera.height;
  rt.samplesPerPixel = options.samplesPerPixel;
  rt.threads = common.threads;
  rt.onRowDone = [&](long long rows) { progress.advance(rows); };
  const RayTracedImage image = renderRayTraced(posed, camera, rays, reference, rt);
  writeImages(options, common, image.radiance, &image.irradiance, "");
}

// A radiosity solution's mesh drawn with its radiance L = B / π (Lambertian) at the corners.
void drawRadiosityMesh(const RenderOptions& options, const CommonOptions& common,
                       const RadiosityMesh& solution, const Camera& camera) {
  const ColoredMesh mesh = radianceMesh(solution);
  const auto context = GlContext::createHeadless();
  MeshRenderer renderer;
  writeImages(options, common, renderer.render(mesh, camera, camera.width, camera.height), nullptr,
              "");
}

// The radiosity solution drawn as its per-vertex mesh.
void renderRadiosity(const RenderOptions& options, const CommonOptions& common,
                     const DynamicScene& live, const Camera& camera) {
  RadiositySolver solver(withThreads(options.radiosity, common));
  solver.build(live);
  drawRadiosityMesh(options, common, solver.mesh(), camera);
}

// The Galerkin core's solution: its leaves' linear functions.
void renderGalerkin(const RenderOptions& options, const CommonOptions& common,
                    const DynamicScene& live, const Camera& camera) {
  GalerkinRadiosity solver(galerkinOptions(options.radiosity, common));
  solver.build(live);
  drawRadiosityMesh(options, common, solver.leafMesh(), camera);
}

// The exact soft shadows: the discontinuity mesh's faces triangulated, each corner's irradiance
// from its face's backprojection, drawn with Gouraud shading (radiance ρE/π on receivers, M/π
// on lights); --edges draws the discontinuity edges over it. `details` gets the mesh's counts.
// With `withoutEdges`, also the picture without the edges (for the exposure).
Image drawDm(const RenderOptions& options, const DiscontinuityMeshEngine& engine,
             const PosedScene& posed, const Camera& camera, MeshRenderer& renderer,
             std::string& details, Image* withoutEdges = nullptr) {
  // Corners about 1/100 of the scene apart resolve the smooth falloff inside large faces.
  const IrradianceMesh solution = buildIrradianceMesh(engine, posed.extent.diagonalLength() / 100);
  const ColoredMesh mesh = radianceMesh(solution, posed);
  std::vector<LineSet> overlays;
  if (options.edges) {
    LineSet lines;
    lines.color = {0.9, 0.1, 0.05};
    for (const auto& [a, b] : solution.edges) {
      lines.endpoints.push_back(a);
      lines.endpoints.push_back(b);
    }
    overlays.push_back(std::move(lines));
  }
  const DmStats& s = engine.stats();
  details = "; mesh: " + std::to_string(s.meshVertices) + " vertices, " +
            std::to_string(s.meshFaces) + " faces, " + std::to_string(solution.indices.size() / 3) +
            " triangles";
  if (withoutEdges) *withoutEdges = renderer.render(mesh, camera, camera.width, camera.height);
  return renderer.render(mesh, overlays, camera, camera.width, camera.height);
}

MeshRenderer::Options dmDrawing() {
  MeshRenderer::Options drawing;
  drawing.unlitBackFaces = true;  // as the ray-traced image: back sides receive nothing
  return drawing;
}

void renderDm(const RenderOptions& options, const CommonOptions& common, const DynamicScene& live,
              const Camera& camera) {
  DiscontinuityMeshEngine engine;
  engine.build(live);
  const auto context = GlContext::createHeadless();
  MeshRenderer renderer(dmDrawing());
  std::string details;
  Image plain;
  const Image image = drawDm(options, engine, live.posed(), camera, renderer, details,
                             options.edges ? &plain : nullptr);
  writeImages(options, common, image, nullptr, details, options.edges ? &plain : nullptr);
}

// The moving exact soft shadows as one strip, frames A..B left to right: one live scene and one
// engine held across the frames, each frame reached by update() (the first built), with each
// frame's update time and a full recomputation's time printed beside it.
void renderDmStrip(const RenderOptions& options, const CommonOptions& common, const Scene& scene,
                   const FrameRange& range, const Camera& camera) {
  DynamicScene live(scene, range.first);
  DiscontinuityMeshEngine engine;
  const auto context = GlContext::createHeadless();
  MeshRenderer renderer(dmDrawing());
  const int frames = range.last - range.first + 1;
  Image strip(camera.width * frames, camera.height);
  std::string details;
  for (int frame = range.first; frame <= range.last; ++frame) {
    auto start = std::chrono::steady_clock::now();
    buildOrStep(live, engine, frame, frame == range.first);
    const double updateSeconds = secondsSince(start);
    start = std::chrono::steady_clock::now();
    {
      const DynamicScene scratchScene(scene, frame);
      DiscontinuityMeshEngine scratch;
      scratch.build(scratchScene);
    }
    const double fullSeconds = secondsSince(start);
    start = std::chrono::steady_clock::now();
    const Image image = drawDm(options, engine, live.posed(), camera, renderer, details);
    const double drawSeconds = secondsSince(start);
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        strip.at((frame - range.first) * camera.width + x, y) = image.at(x, y);
    std::printf("frame %d: %s %.3f s (full recomputation %.3f s), drawn in %.3f s%s\n", frame,
                frame == range.first ? "built in" : "updated in", updateSeconds, fullSeconds,
                drawSeconds, details.c_str());
    std::fflush(stdout);
  }
  writeImages(options, common, strip, nullptr, "");
}

// Exact direct light with radiosity's indirect light, drawn on the discontinuity mesh's faces
// (each corner: the exact direct irradiance plus the indirect one interpolated there).
void renderCombined(const RenderOptions& options, const CommonOptions& common,
                    const DynamicScene& live, const Camera& camera) {
  CombinedSolution solution(withThreads(options.radiosity, common));
  solution.build(live);
  // Corners about 1/100 of the scene apart, as for --method dm.
  const IrradianceMesh mesh = solution.displayMesh(live.posed().extent.diagonalLength() / 100);
  const auto context = GlContext::createHeadless();
  MeshRenderer renderer(dmDrawing());
  writeImages(
      options, common,
      renderer.render(radianceMesh(mesh, live.posed()), camera, camera.width, camera.height),
      nullptr, "");
}

// Shadow volumes: built at frame 0 and updated incrementally to the requested frame.
void renderVolumes(const RenderOptions& options, const CommonOptions& common, const Scene& scene,
                   const Camera& camera) {
  const auto context = GlContext::createHeadless();
  DynamicScene live(scene, 0);
  ShadowVolumeEngine engine;
  engine.build(live);
  walkToFrame(live, options.frame, [&](const SceneChange& change) { engine.update(live, change); });
  const PosedScene& posed = live.posed();
  ShadowVolumeRenderer renderer;
  ShadowVolumeRenderOptions so;
  so.lightSamples = options.lightSamples;
  // The picture shows reflections in mirror polygons; the EXR keeps the quantity of DESIGN.md §5,
  // the direct irradiance of the surface seen (a mirror's own).
  so.mirrors = true;
  const Image radiance = renderer.render(posed, engine, camera, camera.width, camera.height, so);
  Image irradiance;
  if (!options.exr.empty()) {
    so.mirrors = false;
    so.output = ShadowVolumeRenderOptions::Output::kIrradiance;
    irradiance = renderer.render(posed, engine, camera, camera.width, camera.height, so);
  }
  const VolumeUpdateStats& s = engine.stats().frames.back();
  const std::string details = "; volumes: " + std::to_string(s.volumes) + " light x object, " +
                              std::to_string(s.silhouetteEdges) + " silhouette edges, " +
                              std::to_string(engine.stats().jitterIncremental) +
                              " jitter moves incremental, " +
                              std::to_string(engine.stats().jitterRebuilds) + " rebuilt";
  writeImages(options, common, radiance, options.exr.empty() ? nullptr : &irradiance, details);
}

}  // namespace

int runRender(const RenderOptions& options, const CommonOptions& common) {
  if (options.method != "raytrace" && options.method != "radiosity" &&
      options.method != "galerkin" && options.method != "volumes" && options.method != "dm" &&
      options.method != "combined")
    throw UsageError("--method " + options.method +
                     " is not available in this build (available: raytrace, dm, radiosity, "
                     "galerkin, combined, volumes)");
  if (options.edges && options.method != "dm") throw UsageError("--edges needs --method dm");
  // An image written over the scene it was made from would lose the scene.
  for (const std::string& output : {options.output, options.exr}) {
    std::error_code error;
    if (!output.empty() && std::filesystem::equivalent(output, options.scene, error))
      throw UsageError("refusing to write " + output + " over the scene file");
  }
  const Scene scene = loadScene(options.scene);
  checkFrame(options.frame, scene.frames);
  Camera camera = sceneCamera(scene, poseAt(scene, options.frame));
  if (!options.size.empty()) parseSize(options.size, camera);
  if (!options.frames.empty()) {
    if (options.method != "dm") throw UsageError("--frames needs --method dm");
    if (!options.exr.empty()) throw UsageError("--exr is not available with --frames");
    renderDmStrip(options, common, scene, parseFrameRange(options.frames, scene.frames), camera);
    return kOk;
  }
  if (options.method == "volumes") {
    renderVolumes(options, common, scene, camera);
    return kOk;
  }
  const DynamicScene live(scene, options.frame);
  if (options.method == "dm")
    renderDm(options, common, live, camera);
  else if (options.method == "radiosity")
    renderRadiosity(options, common, live, camera);
  else if (options.method == "galerkin")
    renderGalerkin(options, common, live, camera);
  else if (options.method == "combined")
    renderCombined(options, common, live, camera);
  else
    renderRaytrace(options, common, live, camera);
  return kOk;
}

}  // namespace penumbra::cli
