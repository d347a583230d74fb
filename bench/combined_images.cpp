// Issue 19's pictures: `render --method combined` (exact direct light on the discontinuity mesh's
// faces, radiosity's indirect light interpolated at their corners, drawn with OpenGL) beside a
// path-traced image of the same view (the path tracer of lighting/path_traced_reference.h with
// sampled direct light: its visibility is its own shadow rays) and a false-colour image of their
// relative difference, with the median and 95th percentile of that difference over the pixels
// and the seconds each took, one after the other in one run.
//
// Usage: combined_images SCENE.json [--size WxH] [--paths N] [--tolerance T] [--threads T]
//                        [--out DIR]
// (defaults: 320x240, 1,024 paths per pixel, tolerance 1e-3, all threads, the working folder).
// Writes DIR/NAME-combined.png, DIR/NAME-path-traced.png (both at the path-traced image's
// exposure) and DIR/NAME-combined-difference.png: blue where the combined image is darker, red
// where it is brighter, full colour at ±kFullScale, grey where the path-traced pixel is black.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_statistics.h"
#include "penumbra/lighting/path_traced_reference.h"
#include "penumbra/radiosity/combined_solution.h"
#include "penumbra/render/gl_context.h"
#include "penumbra/render/mesh_renderer.h"
#include "penumbra/render/png_writer.h"
#include "penumbra/render/radiance_mesh.h"
#include "penumbra/render/ray_traced_image.h"
#include "penumbra/render/tone_mapping.h"
#include "penumbra/scene/scene_camera.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "penumbra/spatial/ray_caster.h"

using namespace penumbra;
using bench::percentile;

namespace {

constexpr double kFullScale = 0.2;  // a relative difference of ±20% is drawn at full colour

struct Options {
  std::string scene;
  int width = 320, height = 240;
  int paths = 1024;
  double tolerance = 1e-3;
  int threads = 0;
  std::string out = ".";
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int run(const Options& o) {
  const Scene scene = loadScene(o.scene);
  const PosedScene posed = poseAt(scene, 0);
  const DynamicScene live(posed);
  Camera camera = sceneCamera(scene, posed);
  camera.width = o.width;
  camera.height = o.height;

  // The combined solution, drawn as `render --method combined` draws it.
  auto start = std::chrono::steady_clock::now();
  RadiosityOptions radiosity;
  radiosity.tolerance = o.tolerance;
  radiosity.threads = o.threads;
  CombinedSolution combined(radiosity);
  combined.build(live);
  const IrradianceMesh mesh = combined.displayMesh(posed.extent.diagonalLength() / 100);
  const double solveSeconds = secondsSince(start);
  start = std::chrono::steady_clock::now();
  const auto context = GlContext::createHeadless();
  MeshRenderer::Options drawing;
  drawing.unlitBackFaces = true;  // as the ray-traced images: back sides receive nothing
  MeshRenderer renderer(drawing);
  const Image combinedImage =
      renderer.render(radianceMesh(mesh, posed), camera, camera.width, camera.height);
  const double drawSeconds = secondsSince(start);

  // The path tracer at the first hit of each pixel's centre ray.
  start = std::chrono::steady_clock::now();
  const RayCaster rays(posed);
  const PathTracedReference tracer(posed, rays);
  RayTraceOptions rt;
  rt.width = camera.width;
  rt.height = camera.height;
  rt.threads = o.threads;
  const RayTracedImage traced = renderRayTraced(
      posed, camera, rays,
      [&](const Vec3& p, const Vec3& n, PolygonId polygon, std::uint64_t seed) {
        return tracer.irradiance(p, n, polygon, o.paths, 0x5eed0000ull + seed).total();
      },
      rt);
  const double traceSeconds = secondsSince(start);

  // Relative differences of the radiance, over the pixels the path tracer sees lit.
  double mean = 0;
  long long lit = 0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x)
      if (const double v = luminance(traced.radiance.at(x, y)); v > 0) mean += v, ++lit;
  mean /= double(std::max(1LL, lit));
  Image difference(camera.width, camera.height);
  std::vector<double> differences;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const double reference = luminance(traced.radiance.at(x, y));
      if (!(reference > 1e-3 * mean)) {
        difference.at(x, y) = Rgb::gray(0.25);
        continue;
      }
      const double d = luminance(combinedImage.at(x, y)) / reference - 1;
      differences.push_back(std::abs(d));
      const double t = std::clamp(std::abs(d) / kFullScale, 0.0, 1.0);
      difference.at(x, y) = d > 0 ? Rgb{1, 1 - t, 1 - t} : Rgb{1 - t, 1 - t, 1};
    }

  const std::string name = std::filesystem::path(o.scene).stem().string();
  std::filesystem::create_directories(o.out);
  const ToneMapping exposure{autoExposure(traced.radiance)};
  writePng(combinedImage, exposure, o.out + "/" + name + "-combined.png");
  writePng(traced.radiance, exposure, o.out + "/" + name + "-path-traced.png");
  writePng(difference, ToneMapping{1}, o.out + "/" + name + "-combined-difference.png");
  std::printf(
      "%s (%dx%d): combined solution %.2f s + drawing %.2f s; path tracer at %d paths per pixel "
      "%.1f s\n",
      name.c_str(), camera.width, camera.height, solveSeconds, drawSeconds, o.paths, traceSeconds);
  std::printf(
      "  %zu lit pixels: relative difference of the radiance median %.2f%%, p95 %.2f%%, "
      "beyond %.0f%% %.2f%% of them\n",
      differences.size(), 100 * percentile(differences, 0.5), 100 * percentile(differences, 0.95),
      100 * kFullScale,
      100 *
          double(std::count_if(differences.begin(), differences.end(),
                               [](double d) { return d > kFullScale; })) /
          double(std::max<size_t>(1, differences.size())));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", arg.c_str());
        std::exit(1);
      }
      return argv[++i];
    };
    if (arg == "--size") {
      const std::string size = next();
      const auto x = size.find('x');
      if (x == std::string::npos) {
        std::fprintf(stderr, "--size must look like 320x240\n");
        return 1;
      }
      o.width = std::stoi(size.substr(0, x));
      o.height = std::stoi(size.substr(x + 1));
    } else if (arg == "--paths")
      o.paths = std::stoi(next());
    else if (arg == "--tolerance")
      o.tolerance = std::stod(next());
    else if (arg == "--threads")
      o.threads = std::stoi(next());
    else if (arg == "--out")
      o.out = next();
    else
      o.scene = arg;
  }
  if (o.scene.empty()) {
    std::fprintf(stderr,
                 "usage: combined_images SCENE.json [--size WxH] [--paths N] [--tolerance T] "
                 "[--threads T] [--out DIR]\n");
    return 1;
  }
  try {
    return run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "combined_images: %s\n", e.what());
    return 1;
  }
}
