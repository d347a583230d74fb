#include "penumbra/render/mesh_renderer.h"

#include <gtest/gtest.h>

#include "penumbra/render/gl_context.h"

namespace penumbra {
namespace {

// The test camera: at z = 1 looking at the origin with a 90° square view, so the plane z = 0
// shows exactly [-1, 1]² and pixel (i, j) of a kSize² image has its centre at
// x = -1 + (i + 0.5) * 2 / kSize, y = 1 - (j + 0.5) * 2 / kSize.
constexpr int kSize = 64;

Camera testCamera() {
  Camera camera;
  camera.eye = {0, 0, 1};
  camera.target = {0, 0, 0};
  camera.up = {0, 1, 0};
  camera.fovYDegrees = 90;
  return camera;
}

// What a radiance becomes after the float pipeline: one rounding to float, nothing else.
Rgb asFloat(const Rgb& c) {
  return {static_cast<float>(c.r), static_cast<float>(c.g), static_cast<float>(c.b)};
}

// An axis-aligned square [x0, x1] x [y0, y1] at depth z as two triangles.
void addQuad(ColoredMesh& mesh, double x0, double y0, double x1, double y1, double z,
             const Rgb& color, bool counterClockwise = true) {
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}});
  mesh.colors.insert(mesh.colors.end(), 4, color);
  if (counterClockwise) {
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  } else {
    mesh.indices.insert(mesh.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
  }
}

class MeshRendererTest : public ::testing::Test {
 protected:
  void SetUp() override { context_ = GlContext::createHeadless(); }

  std::unique_ptr<GlContext> context_;
};

TEST_F(MeshRendererTest, ConstantQuadGivesExactRadianceInsideAndBackgroundOutside) {
  const Rgb background{0.1, 0.2, 0.3};
  const Rgb radiance{0.3, 1.7, 0.05};  // above 1 on purpose: the image is radiometric
  MeshRenderer renderer({.background = background, .clip = std::nullopt});
  ColoredMesh mesh;
  // [-0.5, 0.5]² covers the pixels 16..47 in both directions; no pixel centre lies on an edge.
  addQuad(mesh, -0.5, -0.5, 0.5, 0.5, 0, radiance);
  const Image image = renderer.render(mesh, testCamera(), kSize, kSize);
  ASSERT_EQ(image.width, kSize);
  ASSERT_EQ(image.height, kSize);
  int inside = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const bool covered = x >= 16 && x < 48 && y >= 16 && y < 48;
      inside += covered;
      ASSERT_EQ(image.at(x, y), asFloat(covered ? radiance : background)) << x << "," << y;
    }
  }
  EXPECT_EQ(inside, 32 * 32);
}

TEST_F(MeshRendererTest, ConstantTriangleInteriorAndOutside) {
  MeshRenderer renderer;
  ColoredMesh mesh;
  mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
  mesh.colors.assign(3, Rgb{2, 0.5, 0.125});
  mesh.indices = {0, 1, 2};
  const Image image = renderer.render(mesh, testCamera(), kSize, kSize);
  EXPECT_EQ(image.at(32, 40), asFloat({2, 0.5, 0.125}));  // centroid region
  EXPECT_EQ(image.at(32, 2), asFloat({2, 0.5, 0.125}));   // near the apex, on the axis
  EXPECT_EQ(image.at(2, 2), Rgb(0, 0, 0));                // left of the apex
  EXPECT_EQ(image.at(61, 10), Rgb(0, 0, 0));
}

TEST_F(MeshRendererTest, GouraudInterpolationIsLinearAcrossTheSurface) {
  MeshRenderer renderer;
  ColoredMesh mesh;
  // The full view, red rising left to right from 0 to 1, green top to bottom from 0 to 1,
  // blue constant: pixel (i, j) must hold ((i + 0.5) / 64, (j + 0.5) / 64, 0.25).
  mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  mesh.colors = {{0, 1, 0.25}, {1, 1, 0.25}, {1, 0, 0.25}, {0, 0, 0.25}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  const Image image = renderer.render(mesh, testCamera(), kSize, kSize);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const Rgb& c = image.at(x, y);
      ASSERT_NEAR(c.r, (x + 0.5) / kSize, 2e-6) << x << "," << y;
      ASSERT_NEAR(c.g, (y + 0.5) / kSize, 2e-6) << x << "," << y;
      ASSERT_EQ(c.b, 0.25);
    }
  }
  EXPECT_NEAR(image.at(10, 40).r, 10.5 / 64, 2e-6);
  EXPECT_NEAR(image.at(10, 40).g, 40.5 / 64, 2e-6);
}

TEST_F(MeshRendererTest, InterpolationIsPerspectiveCorrectOnATiltedQuad) {
  MeshRenderer renderer;
  ColoredMesh mesh;
  // The floor y = -0.5 running away from the camera: radiance = -z (linear in the world). Along
  // the image's centre column, pixel row j sees the floor at depth d = 0.5 / tan(angle below the
  // axis), i.e. z = 1 - d; screen-linear interpolation would get this badly wrong.
  mesh.positions = {{-10, -0.5, 0.5}, {10, -0.5, 0.5}, {10, -0.5, -20}, {-10, -0.5, -20}};
  mesh.colors = {Rgb::gray(-0.5), Rgb::gray(-0.5), Rgb::gray(20), Rgb::gray(20)};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  const Image image = renderer.render(mesh, testCamera(), kSize, kSize);
  for (int j : {40, 45, 50, 60}) {
    const double tanBelow = ((j + 0.5) / kSize * 2 - 1);  // 90° view: ndc y = tan(angle)
    const double depth = 0.5 / tanBelow;
    const double expected = depth - 1;  // -z with z = 1 - depth
    EXPECT_NEAR(image.at(31, j).r, expected, 1e-4 * (1 + expected)) << j;
  }
}

TEST_F(MeshRendererTest, BothSidesOfAPolygonAreVisible) {
  MeshRenderer renderer;
  ColoredMesh mesh;
  addQuad(mesh, -0.5, -0.5, 0.5, 0.5, 0, {1, 1, 1}, /*counterClockwise=*/false);
  const Image image = renderer.render(mesh, testCamera(), kSize, kSize);
  EXPECT_EQ(image.at(32, 32), Rgb(1, 1, 1));
}

TEST_F(MeshRendererTest, NearerSurfaceWinsWhateverTheDrawOrder) {
  MeshRenderer renderer;
  const Rgb nearColor{0, 1, 0}, farColor{1, 0, 0};
  for (bool nearFirst : {true, false}) {
    ColoredMesh mesh;
    if (nearFirst) addQuad(mesh, -0.5, -0.5, 0.5, 0.5, 0, nearColor);
    addQuad(mesh, -2, -2, 2, 2, -1, farColor);  // fills the view at distance 2
    if (!nearFirst) addQuad(mesh, -0.5, -0.5, 0.5, 0.5, 0, nearColor);
    const Image image = renderer.render(mesh, testCamera(), kSize, kSize);
    EXPECT_EQ(image.at(32, 32), nearColor) << nearFirst;
    EXPECT_EQ(image.at(20, 40), nearColor) << nearFirst;
    EXPECT_EQ(image.at(2, 2), farColor) << nearFirst;
    EXPECT_EQ(image.at(60, 33), farColor) << nearFirst;
  }
}

TEST_F(MeshRendererTest, OverlayLinesShowOnSurfacesAndHideBehindThem) {
  MeshRenderer renderer;
  const Rgb surface{0.5, 0.5, 0.5}, onSurface{0, 0, 1}, hidden{1, 0, 0}, free{0, 1, 0};
  ColoredMesh mesh;
  addQuad(mesh, -0.5, -0.5, 0.5, 0.5, 0, surface);
  const double row20 = 1 - 20.5 / 32;  // world y of pixel row 20's centres on z = 0
  const double row24 = 1 - 24.5 / 32;
  const double row5 = (1 - 5.5 / 32) * 1.5;  // row 5 on the plane z = -0.5 (distance 1.5)
  const std::vector<LineSet> overlays = {
      {{{-0.5, row20, 0}, {0.5, row20, 0}}, onSurface},                 // lies on the quad
      {{{-0.4, row24 * 1.5, -0.5}, {0.4, row24 * 1.5, -0.5}}, hidden},  // behind the quad
      {{{-0.4, row5, -0.5}, {0.4, row5, -0.5}}, free},  // behind, but above the quad
  };
  const Image image = renderer.render(mesh, overlays, testCamera(), kSize, kSize);
  for (int x = 24; x < 40; ++x) {
    EXPECT_EQ(image.at(x, 20), onSurface) << x;
    EXPECT_EQ(image.at(x, 24), surface) << x;
    EXPECT_EQ(image.at(x, 5), free) << x;
  }
  EXPECT_EQ(image.at(32, 30), surface);
  // Without overlays the same renderer draws the plain mesh again.
  EXPECT_EQ(renderer.render(mesh, testCamera(), kSize, kSize).at(32, 20), surface);
}

TEST_F(MeshRendererTest, InfiniteFarPlaneKeepsVeryDistantGeometry) {
  ColoredMesh mesh;
  addQuad(mesh, -1e6, -1e6, 1e6, 1e6, -1e5, {0.75, 0.75, 0.75});  // far wall
  addQuad(mesh, -0.5, -0.5, 0.5, 0.5, 0, {0, 0, 1});              // near quad in front
  MeshRenderer infinite({.background = {}, .clip = ClipRange{0.5, 0, true}});
  const Image image = infinite.render(mesh, testCamera(), kSize, kSize);
  EXPECT_EQ(image.at(2, 2), Rgb(0.75, 0.75, 0.75));
  EXPECT_EQ(image.at(32, 32), Rgb(0, 0, 1));
  MeshRenderer finite({.background = {}, .clip = ClipRange{0.5, 100, false}});
  EXPECT_EQ(finite.render(mesh, testCamera(), kSize, kSize).at(2, 2), Rgb(0, 0, 0));
}

TEST_F(MeshRendererTest, FarFromTheOriginGivesTheSameImage) {
  // Vertex data goes to the GPU relative to the eye, so a scene a thousand kilometres from the
  // origin renders exactly like the same scene at the origin.
  MeshRenderer renderer;
  const Vec3 offset{1e6, -2e6, 3e6};
  ColoredMesh mesh, moved;
  addQuad(mesh, -0.5, -0.5, 0.5, 0.5, 0, {0.3, 0.6, 0.9});
  mesh.colors[2] = {1, 0, 0};  // some interpolation too
  moved = mesh;
  for (Vec3& p : moved.positions) p += offset;
  Camera camera = testCamera();
  camera.eye += offset;
  camera.target += offset;
  const Image a = renderer.render(mesh, testCamera(), kSize, kSize);
  const Image b = renderer.render(moved, camera, kSize, kSize);
  EXPECT_EQ(a.pixels, b.pixels);
}

TEST_F(MeshRendererTest, SizeFollowsTheRequestAndAspectIsWidthOverHeight) {
  MeshRenderer renderer;
  ColoredMesh mesh;
  addQuad(mesh, -0.5, -0.5, 0.5, 0.5, 0, {1, 1, 1});
  // 128 x 64: the 90° vertical view shows y in [-1, 1] and x in [-2, 2]; the quad covers the
  // columns 48..79 and the rows 16..47.
  const Image image = renderer.render(mesh, testCamera(), 128, 64);
  ASSERT_EQ(image.width, 128);
  ASSERT_EQ(image.height, 64);
  EXPECT_EQ(image.at(48, 16), Rgb(1, 1, 1));
  EXPECT_EQ(image.at(79, 47), Rgb(1, 1, 1));
  EXPECT_EQ(image.at(47, 30), Rgb(0, 0, 0));
  EXPECT_EQ(image.at(80, 30), Rgb(0, 0, 0));
  EXPECT_EQ(image.at(60, 15), Rgb(0, 0, 0));
  EXPECT_EQ(image.at(60, 48), Rgb(0, 0, 0));
  // An empty mesh is only background.
  const Image empty = renderer.render(ColoredMesh{}, testCamera(), 8, 8);
  for (const Rgb& c : empty.pixels) EXPECT_EQ(c, Rgb(0, 0, 0));
}

}  // namespace
}  // namespace penumbra
