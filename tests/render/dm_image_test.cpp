// The exact soft shadows drawn as a mesh (`render --method dm`) against the ray-traced image of the
// same exact reference: no pixel the mesh draws black where the ray-traced image and its
// neighbourhood are lit (the single-pixel specks that back sides tying in depth with front sides
// along every crease, and faces under a contact, used to leave), and every corner value finite
// and non-negative, contact corners included.

#include <gtest/gtest.h>

#include <numbers>

#include "penumbra/dm/irradiance_mesh.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/render/gl_context.h"
#include "penumbra/render/mesh_renderer.h"
#include "penumbra/render/radiance_mesh.h"
#include "penumbra/render/ray_traced_image.h"
#include "penumbra/scene/scene_camera.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

double brightness(const Rgb& c) {
  return c.r + c.g + c.b;
}

class DmImage : public testing::TestWithParam<const char*> {};

TEST_P(DmImage, NoBlackSpecksWhereTheRayTracedImageIsLit) {
  const Scene scene = loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + GetParam());
  const DynamicScene live(scene, 0);
  DiscontinuityMeshEngine engine;
  engine.build(live);
  const IrradianceMesh solution = buildIrradianceMesh(engine, live.extent().diagonalLength() / 100);
  for (const Rgb& e : solution.irradiance) {
    ASSERT_TRUE(e.isFinite());
    ASSERT_GE(std::min({e.r, e.g, e.b}), -1e-12);
  }
  Camera camera = sceneCamera(scene, live.posed());
  const int width = 400, height = 300;
  const auto context = GlContext::createHeadless();
  MeshRenderer::Options drawing;
  drawing.unlitBackFaces = true;
  MeshRenderer renderer(drawing);
  const Image mesh = renderer.render(radianceMesh(solution, live.posed()), camera, width, height);
  const ExactReference reference(live.posed(), &live.grid());
  RayTraceOptions options;
  options.width = width;
  options.height = height;
  const Image traced =
      renderRayTraced(live.posed(), camera, live.rays(), reference, options).radiance;
  // Lit: a tenth of the image's mean radiance. A speck: black in the mesh image, lit in the
  // ray-traced one at the pixel and its four neighbours.
  double mean = 0;
  for (const Rgb& c : traced.pixels) mean += brightness(c) / double(traced.pixels.size());
  int specks = 0, lit = 0;
  for (int y = 1; y + 1 < height; ++y)
    for (int x = 1; x + 1 < width; ++x) {
      bool allLit = true;
      for (const auto& [dx, dy] : {std::pair{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}})
        allLit = allLit && brightness(traced.at(x + dx, y + dy)) > 0.1 * mean;
      lit += allLit;
      if (allLit && brightness(mesh.at(x, y)) < 1e-3 * mean) ++specks;
    }
  EXPECT_GT(lit, width * height / 3);
  EXPECT_EQ(specks, 0) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Bundled, DmImage,
                         testing::Values("office-desk/desk-475.json",
                                         "cornell-box/cornell-box.json"),
                         [](const testing::TestParamInfo<const char*>& info) {
                           return std::string(info.param).find("desk") != std::string::npos
                                      ? std::string("desk475")
                                      : std::string("cornell");
                         });

}  // namespace
}  // namespace penumbra
