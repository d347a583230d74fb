#pragma once
// The reference image (`penumbra render --method raytrace`): a pinhole camera casts one ray per
// pixel sample (Embree); at the first hit the direct irradiance is the exact reference of
// DESIGN.md §5, so the image shows exact soft shadows with no mesh and no sampling noise in the
// penumbra. Radiance of a Lambertian surface: L = ρ/π · E (+ M/π on a light's front side).

#include <cstdint>
#include <functional>

#include "penumbra/render/image.h"
#include "penumbra/scene/camera.h"
#include "penumbra/scene/posed_scene.h"

namespace penumbra {

class ExactReference;
class RayCaster;

struct RayTraceOptions {
  int width = 640;
  int height = 480;
  int samplesPerPixel = 1;  // 1: the pixel centre; n > 1: n stratified jittered samples (seeded)
  int threads = 0;          // 0: all hardware threads
  std::function<void(long long rowsDone)> onRowDone;  // progress; may be called from any thread
};

struct RayTracedImage {
  Image radiance;    // W/(m²·sr) per channel, row 0 at the top
  Image irradiance;  // direct irradiance E at the first hit (0 on back faces and misses)
};

RayTracedImage renderRayTraced(const PosedScene& scene, const Camera& camera,
                               const RayCaster& rays, const ExactReference& reference,
                               const RayTraceOptions& options);

// The same camera and shading with any irradiance at the first hit: a path tracer's total, or a
// solution's samples (bench/combined_images). `seed` is distinct per pixel sample and the same in
// every run, so a sampled irradiance gives the same image for any number of threads.
using IrradianceAtHit =
    std::function<Rgb(const Vec3& p, const Vec3& n, PolygonId polygon, std::uint64_t seed)>;
RayTracedImage renderRayTraced(const PosedScene& scene, const Camera& camera,
                               const RayCaster& rays, const IrradianceAtHit& irradianceAt,
                               const RayTraceOptions& options);

}  // namespace penumbra
