#pragma once
// The reference image (`penumbra render --method raytrace`): a pinhole camera casts one ray per
// pixel sample (Embree); at the first hit the direct irradiance is the exact reference of
// DESIGN.md §5, so the image shows exact soft shadows with no mesh and no sampling noise in the
// penumbra. Radiance of a Lambertian surface: L = ρ/π · E (+ M/π on a light's front side).

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

}  // namespace penumbra
