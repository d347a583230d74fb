#pragma once
// Rasterises triangle meshes that carry linear radiance per vertex (Gouraud interpolation) into a
// float framebuffer and reads the result back as a radiometric Image: the display path shared by
// the discontinuity-mesh and radiosity engines, whose solutions are radiance at mesh vertices.
// Tone mapping happens afterwards on the CPU (tone_mapping.h).
//
// Drawing: depth test on, no back-face culling (polygons are visible from both sides; see
// Options::unlitBackFaces), no lighting, no multisampling (pixel values are exact interpolations,
// so tests can compare them).

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "penumbra/base/rgb.h"
#include "penumbra/geometry/box.h"
#include "penumbra/geometry/vec3.h"
#include "penumbra/render/image.h"
#include "penumbra/render/view_projection.h"
#include "penumbra/scene/camera.h"

namespace penumbra {

// Triangles with per-vertex radiance (linear, W/(m² sr) per channel, not display values).
// Invariants checked by MeshRenderer: colors.size() == positions.size(), indices.size() % 3 == 0,
// every index < positions.size().
struct ColoredMesh {
  std::vector<Vec3> positions;
  std::vector<Rgb> colors;
  std::vector<std::uint32_t> indices;  // three per triangle

  Box3 bounds() const;
};

// Line segments drawn over a mesh in one colour (discontinuity-mesh edges, element outlines).
// endpoints holds pairs: segment i runs from endpoints[2i] to endpoints[2i+1].
struct LineSet {
  std::vector<Vec3> endpoints;
  Rgb color;
};

class MeshRenderer {
 public:
  struct Options {
    Rgb background{0, 0, 0};
    // Near / far planes; when unset, clipRangeFor(camera, bounds of mesh and lines) per render.
    std::optional<ClipRange> clip;
    // Triangles are counter-clockwise seen from their lit side, and their back sides receive
    // nothing (the exact soft shadows; the ray-traced image draws back sides black too): back
    // sides are drawn black and lose every depth tie with front sides.
    bool unlitBackFaces = false;
  };

  // Precondition: a GL context (GlContext) is current and stays current for every call; the
  // renderer's GL objects belong to it. Throws RenderError if its shaders cannot be built.
  MeshRenderer();
  explicit MeshRenderer(const Options& options);
  ~MeshRenderer();
  MeshRenderer(const MeshRenderer&) = delete;
  MeshRenderer& operator=(const MeshRenderer&) = delete;

  const Options& options() const { return options_; }
  void setOptions(const Options& options) { options_ = options; }

  // A width x height image of the mesh seen from `camera` (aspect from width / height; the
  // camera's own size is ignored). Pixels no triangle covers hold options().background.
  // Preconditions: width, height > 0; the mesh invariants above. Throws RenderError on GL errors.
  Image render(const ColoredMesh& mesh, const Camera& camera, int width, int height);

  // As above, with `overlays` drawn over the mesh: lines lying on a surface stay visible (the
  // mesh is pushed back by a polygon offset), lines behind nearer surfaces are hidden.
  // Precondition: each overlay has an even number of endpoints.
  Image render(const ColoredMesh& mesh, const std::vector<LineSet>& overlays, const Camera& camera,
               int width, int height);

 private:
  struct GlState;

  Options options_;
  std::unique_ptr<GlState> gl_;
};

}  // namespace penumbra
