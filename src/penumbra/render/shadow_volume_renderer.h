#pragma once
// Draws a frame lit by point lights with stencil shadow volumes (the volumes engine,
// volumes/shadow_volume_engine.h), and soft shadows by averaging jittered point lights.
//
// Papers: Everitt & Kilgard, "Practical and Robust Stenciled Shadow Volumes for
// Hardware-Accelerated Rendering" (2002): z-fail counting with two-sided stencil, far plane at
// infinity plus depth clamp so that caps at w = 0 are never clipped, near caps pushed back by a
// polygon offset so that a lit surface never fights its own cap; McReynolds & Blythe, "Advanced
// Graphics Programming Techniques Using OpenGL", §11.3.2.3 (jittered lights accumulated in a float
// buffer, reflected volumes, and the stencil-masked planar-mirror composite); Heckbert & Herf 1997
// (soft shadows as an average of hard ones).
//
// Mirrors (options.mirrors): for each group of coplanar mirror polygons (volumes/mirror_planes.h),
// the pixels where the mirror's front is seen are marked in the stencil, their depth reset to far,
// and the scene reflected through the mirror plane (clipped at it, lit by the reflected light
// samples with the reflected volumes) is drawn there only, times the mirror's reflectance; then
// the scene itself is drawn in every other pixel. One bounce: inside a reflection, mirrors are
// ordinary diffuse surfaces. Stencil layout: bit 7 marks pixels already given to a mirror, bit 6
// the mirror being drawn, bits 0-5 count shadow volumes modulo 64 (a pixel needs 64 nested
// volumes along its ray to be counted lit wrongly).
//
// Radiometry (DESIGN.md §5): a point sample y of a light with exitance M and area A, standing for
// area A / N, gives irradiance E = M (A / N) cos θp cos θy / (π r²) (θy measured from the light's
// front normal; nothing behind the light). Radiance L = ρ / π · Σ E + M / π on a light's front
// face. With N stratified samples the average converges to the exact image of
// render/ray_traced_image.h (its `irradiance` is what `Output::kIrradiance` draws).

#include <cstdint>
#include <memory>
#include <optional>

#include "penumbra/geometry/transform.h"
#include "penumbra/render/image.h"
#include "penumbra/scene/camera.h"
#include "penumbra/scene/posed_scene.h"
#include "penumbra/volumes/shadow_volume_engine.h"

namespace penumbra {

struct ShadowVolumeRenderOptions {
  enum class Output { kRadiance, kIrradiance };
  int lightSamples = 1;  // per light; 1: the light's centroid (hard shadows)
  Output output = Output::kRadiance;
  // Draw everything under this transform (a planar reflection): the scene's polygons, the light
  // samples, and the engine's volumes mapped by it — the reflected light's volume is the
  // original one transformed, not a rebuild.
  // Precondition: not together with `mirrors`.
  std::optional<Transform> reflection;
  // Show the reflected scene in the front of every mirror polygon (see above); when false, mirror
  // polygons are drawn as diffuse surfaces with their reflectance.
  bool mirrors = false;
  std::uint64_t seed = 1;  // jitter of the stratified light samples
};

class ShadowVolumeRenderer {
 public:
  // Precondition: a GL context (GlContext) is current and stays current for every call.
  ShadowVolumeRenderer();
  ~ShadowVolumeRenderer();
  ShadowVolumeRenderer(const ShadowVolumeRenderer&) = delete;
  ShadowVolumeRenderer& operator=(const ShadowVolumeRenderer&) = delete;

  // A width x height image of `scene` seen from `camera`. `engine` holds the volumes of the same
  // frame (built or updated to scene.frame); its lights are jittered over their polygons and left
  // at their centroids afterwards. Preconditions: width, height > 0; lightSamples >= 1.
  // Throws RenderError on GL errors.
  Image render(const PosedScene& scene, ShadowVolumeEngine& engine, const Camera& camera, int width,
               int height, const ShadowVolumeRenderOptions& options);

 private:
  struct GlState;
  struct Pass;
  // Draws `pass` into the pixels it owns: depth and emission, then each light sample's volumes
  // and lighting.
  void drawPass(const PosedScene& scene, ShadowVolumeEngine& engine, const Pass& pass,
                const ShadowVolumeRenderOptions& options);

  std::unique_ptr<GlState> gl_;
};

}  // namespace penumbra
