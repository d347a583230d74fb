#include "penumbra/render/shadow_volume_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <string>

#include "penumbra/lighting/exact_reference.h"
#include "penumbra/render/gl_context.h"
#include "penumbra/render/ray_traced_image.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {
namespace {

Scene load(const std::string& relative) {
  return loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + relative);
}

// Direct irradiance from each light's centroid at `p` (normal `n`) with a ray-cast shadow test.
Rgb hardIrradiance(const PosedScene& scene, const RayCaster& rays, const Vec3& p, const Vec3& n) {
  Rgb e;
  for (PolygonId id : scene.lights) {
    const WorldPolygon& light = scene.polygons[id];
    const Vec3 y0 = centroid(light.vertices);
    const Vec3 d = y0 - p;
    const double r2 = dot(d, d), r = std::sqrt(r2);
    const double cosP = dot(n, d) / r;
    const double cosY = -dot(light.plane.normal, d) / r;
    if (cosP <= 0 || cosY <= 0 || rays.isOccluded(p, y0)) continue;
    e += scene.materialOf(light).emission * (light.area * cosP * cosY / (std::numbers::pi * r2));
  }
  return e;
}

// Per pixel centre, the direct irradiance of the surface seen, from each light's centroid with a
// ray-cast shadow test: the CPU oracle for hard shadows (same pinhole model as
// render/ray_traced_image.cpp). With `mirrors`, a ray meeting the front of a mirror polygon is
// reflected once and the pixel gets the mirror's reflectance times the irradiance of what the
// reflected ray meets (mirrors met by the reflected ray count as diffuse surfaces: one bounce).
Image rayCastHardShadows(const PosedScene& scene, const Camera& camera, int width, int height,
                         bool mirrors = false) {
  const RayCaster rays(scene);
  const Vec3 forward = normalize(camera.target - camera.eye);
  const Vec3 right = normalize(cross(forward, camera.up));
  const Vec3 up = cross(right, forward);
  const double tanHalf = std::tan(camera.fovYDegrees * std::numbers::pi / 360);
  const double aspect = double(width) / height;
  const double inf = std::numeric_limits<double>::infinity();
  Image image(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double ndcX = 2 * (x + 0.5) / width - 1, ndcY = 1 - 2 * (y + 0.5) / height;
      Vec3 dir = normalize(forward + right * (ndcX * tanHalf * aspect) + up * (ndcY * tanHalf));
      auto hit = rays.intersect(camera.eye, dir, 0, inf);
      if (!hit) continue;
      const WorldPolygon* polygon = &scene.polygons[hit->polygon];
      if (dot(dir, polygon->plane.normal) >= 0) continue;
      Rgb weight{1, 1, 1};
      if (mirrors && scene.materialOf(*polygon).mirror && !polygon->isLight) {
        const Vec3 n = polygon->plane.normal;
        const Vec3 q = polygon->plane.project(hit->point);
        dir = dir - n * (2 * dot(dir, n));
        weight = scene.materialOf(*polygon).reflectance;
        hit = rays.intersect(q, dir, rays.epsilon(), inf, polygon->id);
        if (!hit) continue;
        polygon = &scene.polygons[hit->polygon];
        if (dot(dir, polygon->plane.normal) >= 0) continue;
      }
      const Vec3 p = polygon->plane.project(hit->point);
      image.at(x, y) = weight * hardIrradiance(scene, rays, p, polygon->plane.normal);
    }
  }
  return image;
}

double luminance(const Rgb& c) {
  return (c.r + c.g + c.b) / 3;
}

struct PixelComparison {
  int differing = 0;  // pixels whose irradiance differs by more than the shading tolerance
  int offEdges = 0;   // of them, pixels none of whose neighbours is an edge in the oracle's image
  int unlit = 0;      // pixels the oracle finds black
};

// Compares a GPU irradiance image with the CPU oracle's. A pixel differs when lit in one and
// shadowed in the other (or sees another surface): the shading itself agrees to float precision,
// far below the 0.5% threshold. An edge pixel: a neighbour in the oracle's image is lit while it
// is not (or the reverse), or sees a surface whose irradiance differs by more than 20% (a
// geometric edge, a mirror's border).
PixelComparison comparePixels(const Image& gpu, const Image& cpu) {
  const int width = cpu.width, height = cpu.height;
  double maxE = 0;
  for (const Rgb& c : cpu.pixels) maxE = std::max(maxE, luminance(c));
  auto isEdge = [&](int x, int y) {
    const double b = luminance(cpu.at(x, y));
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
        const double c = luminance(cpu.at(nx, ny));
        if ((c > 1e-4 * maxE) != (b > 1e-4 * maxE) || std::abs(c - b) > 0.2 * std::max(b, c))
          return true;
      }
    return false;
  };
  PixelComparison result;
  for (size_t i = 0; i < cpu.pixels.size(); ++i) {
    const double a = luminance(gpu.pixels[i]), b = luminance(cpu.pixels[i]);
    if (std::abs(a - b) > 5e-3 * b + 1e-4 * maxE) {
      ++result.differing;
      if (!isEdge(int(i % width), int(i / width))) ++result.offEdges;
      if (getenv("PENUMBRA_DEBUG_PIXELS"))
        std::printf("  px %zu,%zu gpu %g cpu %g\n", i % width, i / width, a, b);
    }
    if (b == 0) ++result.unlit;
  }
  return result;
}

class ShadowVolumeRendererTest : public ::testing::Test {
 protected:
  void SetUp() override { context_ = GlContext::createHeadless(); }
  std::unique_ptr<GlContext> context_;
};

TEST_F(ShadowVolumeRendererTest, HardShadowsEqualRayCastShadowTestPerPixel) {
  constexpr int kWidth = 640, kHeight = 480;
  ShadowVolumeRenderer renderer;
  for (const std::string file :
       {"cornell-box/cornell-box.json", "office-desk/desk-145.json", "office-desk/desk-475.json"}) {
    const Scene scene = load(file);
    ShadowVolumeEngine engine;
    engine.build(scene, 0);
    for (int frame = 0; frame < scene.frames; ++frame) {
      if (frame > 0) engine.update(scene, frame);
      const PosedScene posed = poseAt(scene, frame);
      ShadowVolumeRenderOptions options;
      options.output = ShadowVolumeRenderOptions::Output::kIrradiance;
      const Image gpu = renderer.render(posed, engine, *scene.camera, kWidth, kHeight, options);
      const Image cpu = rayCastHardShadows(posed, *scene.camera, kWidth, kHeight);
      const PixelComparison c = comparePixels(gpu, cpu);
      const double fraction = double(c.differing) / double(cpu.pixels.size());
      std::printf("%s frame %d: %d of %zu pixels differ (%.4f%%), %d of them off edges, %d unlit\n",
                  file.c_str(), frame, c.differing, cpu.pixels.size(), 100 * fraction, c.offEdges,
                  c.unlit);
      // Measured on llvmpipe: at most 0.0889% of the pixels differ (desk-475), all on edges but
      // for at most 8 of 307,200.
      EXPECT_LT(fraction, 1e-3) << file << " frame " << frame;
      // Off edges the two agree but for isolated single pixels (a sub-pixel sliver of shadow or
      // surface that only one pixel centre catches, so no neighbour shows it): at most 1e-4.
      EXPECT_LE(c.offEdges, int(cpu.pixels.size() / 10000)) << file << " frame " << frame;
      EXPECT_GT(c.unlit, 0);
      // Without mirror polygons the mirror composite must change nothing.
      options.mirrors = true;
      const Image withMirrors =
          renderer.render(posed, engine, *scene.camera, kWidth, kHeight, options);
      EXPECT_EQ(withMirrors.pixels, gpu.pixels) << file << " frame " << frame;
    }
  }
}

TEST_F(ShadowVolumeRendererTest, JitteredSoftShadowsConvergeToTheExactImage) {
  constexpr int kWidth = 160, kHeight = 120;
  ShadowVolumeRenderer renderer;
  for (const std::string file : {"cornell-box/cornell-box.json", "office-desk/desk-145.json"}) {
    const Scene scene = load(file);
    const PosedScene posed = poseAt(scene, 1);
    const UniformGrid grid(posed);
    const ExactReference reference(posed, &grid);
    const RayCaster rays(posed);
    RayTraceOptions rt;
    rt.width = kWidth;
    rt.height = kHeight;
    const Image exact = renderRayTraced(posed, *scene.camera, rays, reference, rt).irradiance;
    ShadowVolumeEngine engine;
    engine.build(scene, 1);
    std::printf("%s: N, mean |E - exact| / mean exact over lit pixels\n", file.c_str());
    std::vector<double> errors;
    for (int n : {1, 4, 16, 64, 256}) {
      ShadowVolumeRenderOptions options;
      options.output = ShadowVolumeRenderOptions::Output::kIrradiance;
      options.lightSamples = n;
      const Image image = renderer.render(posed, engine, *scene.camera, kWidth, kHeight, options);
      double error = 0, total = 0;
      for (size_t i = 0; i < exact.pixels.size(); ++i) {
        const double b = luminance(exact.pixels[i]);
        if (b <= 0) continue;
        error += std::abs(luminance(image.pixels[i]) - b);
        total += b;
      }
      errors.push_back(error / total);
      std::printf("  N = %3d  error %.4f%%\n", n, 100 * errors.back());
    }
    // 256 jittered hard-shadow images against the exact image: measured 0.115% (Cornell box) and
    // 0.130% (desk-145) on llvmpipe; the bound is about 4x that (it was 2%).
    EXPECT_LT(errors.back(), 5e-3) << file;
    EXPECT_LT(errors[4], errors[0]) << file;
    EXPECT_LT(errors[3], errors[1]) << file;
    EXPECT_LT(errors[2], errors[0]) << file;
  }
}

TEST_F(ShadowVolumeRendererTest, ReflectedVolumesRenderTheMirroredScene) {
  constexpr int kWidth = 200, kHeight = 150;
  const Scene scene = load("office-desk/desk-145.json");
  const double frame = 2;
  const PosedScene posed = poseAt(scene, frame);
  // Mirror left-right through the middle of the room, so the camera still sees it all.
  const Vec3 n = normalize(Vec3{1, 0, 0.2});
  const double offset = dot(n, posed.bounds.center());
  Transform reflection;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) reflection.linear.m[i][j] = (i == j) - 2 * n[i] * n[j];
  reflection.translation = n * (2 * offset);
  Scene mirrored = scene;
  for (SceneObject& object : mirrored.objects) {
    const Transform t = object.transformAt(frame);
    for (Polygon3& polygon : object.polygons) {
      for (Vec3& v : polygon) v = reflection.applyToPoint(t.applyToPoint(v));
      std::reverse(polygon.begin() + 1, polygon.end());
    }
    object.motion = Motion();
    object.transform = TrsPose{};
  }
  ShadowVolumeRenderer renderer;
  ShadowVolumeEngine engine, mirroredEngine;
  engine.build(scene, 0);
  engine.update(scene, frame);
  mirroredEngine.build(mirrored, 0);
  ShadowVolumeRenderOptions options;
  options.reflection = reflection;
  const Image viaReflection =
      renderer.render(posed, engine, *scene.camera, kWidth, kHeight, options);
  const Image direct = renderer.render(poseAt(mirrored, 0), mirroredEngine, *scene.camera, kWidth,
                                       kHeight, ShadowVolumeRenderOptions{});
  int differing = 0, lit = 0;
  for (size_t i = 0; i < direct.pixels.size(); ++i) {
    const double a = luminance(viaReflection.pixels[i]), b = luminance(direct.pixels[i]);
    if (std::abs(a - b) > 1e-4 * b + 1e-6) ++differing;
    if (b > 0) ++lit;
  }
  std::printf("reflection: %d of %zu pixels differ\n", differing, direct.pixels.size());
  EXPECT_GT(lit, int(direct.pixels.size() / 2));
  // Measured 0 on llvmpipe. Not 0 here: the two paths round differently (the reflection applied
  // to the vertices by the GPU against mirrored coordinates computed on the CPU), so on another
  // driver a pixel centre lying on an edge may fall on either side: at most 3 of 30,000.
  EXPECT_LE(differing, int(direct.pixels.size() / 10000));
}

// The stencil-masked planar-mirror composite against a CPU ray cast with one mirror bounce, over
// the motion of the Cornell box whose left wall is a mirror: the image in the mirror (the room
// reflected, with its reflected shadows) and the room around it, pixel for pixel but for edges.
TEST_F(ShadowVolumeRendererTest, MirrorCompositeEqualsOneBounceRayCast) {
  constexpr int kWidth = 512, kHeight = 512;
  ShadowVolumeRenderer renderer;
  const Scene scene = load("cornell-box/cornell-mirror.json");
  ShadowVolumeEngine engine;
  engine.build(scene, 0);
  for (int frame = 0; frame < scene.frames; ++frame) {
    if (frame > 0) engine.update(scene, frame);
    const PosedScene posed = poseAt(scene, frame);
    ShadowVolumeRenderOptions options;
    options.output = ShadowVolumeRenderOptions::Output::kIrradiance;
    options.mirrors = true;
    const Image gpu = renderer.render(posed, engine, *scene.camera, kWidth, kHeight, options);
    const Image cpu = rayCastHardShadows(posed, *scene.camera, kWidth, kHeight, true);
    const PixelComparison c = comparePixels(gpu, cpu);
    // What the mirror shows, by the oracle: pixels whose primary ray meets the mirror, and
    // among them the reflected shadows (black where the reflected ray meets a lit-side surface).
    const Image direct = rayCastHardShadows(posed, *scene.camera, kWidth, kHeight, false);
    options.mirrors = false;
    const Image plain = renderer.render(posed, engine, *scene.camera, kWidth, kHeight, options);
    int changedByMirror = 0, differFromPlain = 0, reflectedShadow = 0;
    for (size_t i = 0; i < cpu.pixels.size(); ++i) {
      if (cpu.pixels[i] != direct.pixels[i]) ++changedByMirror;
      // The (lit) mirror wall shows a shadow: the reflected ray meets a shadowed point.
      if (luminance(cpu.pixels[i]) == 0 && luminance(direct.pixels[i]) > 0) ++reflectedShadow;
      if (gpu.pixels[i] != plain.pixels[i]) ++differFromPlain;
    }
    const double fraction = double(c.differing) / double(cpu.pixels.size());
    std::printf(
        "mirror frame %d: %d of %zu pixels differ (%.4f%%), %d off edges; %d pixels show "
        "the reflection (%d changed on the GPU), %d of them in reflected shadow, %d unlit\n",
        frame, c.differing, cpu.pixels.size(), 100 * fraction, c.offEdges, changedByMirror,
        differFromPlain, reflectedShadow, c.unlit);
    // Measured on llvmpipe: at most 0.0191% of the pixels differ, at most 1 of them off edges.
    EXPECT_LT(fraction, 1e-3) << "frame " << frame;
    EXPECT_LE(c.offEdges, int(cpu.pixels.size() / 50000)) << "frame " << frame;
    // The mirror covers a good part of the view, so the comparison is about the reflection.
    EXPECT_GT(changedByMirror, int(cpu.pixels.size() / 10)) << "frame " << frame;
    EXPECT_GT(differFromPlain, int(cpu.pixels.size() / 10)) << "frame " << frame;
    // ... and the blocks' shadows are seen in it, so the reflected volumes are exercised.
    EXPECT_GT(reflectedShadow, int(cpu.pixels.size() / 200)) << "frame " << frame;
  }
}

}  // namespace
}  // namespace penumbra
