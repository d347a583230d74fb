#include "penumbra/scene/closedness.h"

#include <gtest/gtest.h>

#include "support/scene_builder.h"

namespace penumbra {
namespace {

// Outward-facing unit cube faces.
std::vector<Polygon3> cube(double x0, double y0, double z0, double s) {
  const double x1 = x0 + s, y1 = y0 + s, z1 = z0 + s;
  return {{{x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}},   // -z
          {{x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}},   // +z
          {{x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1}},   // -y
          {{x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1}, {x1, y1, z0}},   // +y
          {{x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0}},   // -x
          {{x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}}};  // +x
}

TEST(Closedness, CubeIsClosedAndLosingAFaceOpensIt) {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  for (const Polygon3& f : cube(0, 0, 0, 1)) b.addPolygon("white", f, "cube");
  const std::vector<Polygon3> faces = cube(3, 0, 0, 1);
  for (size_t i = 0; i + 1 < faces.size(); ++i) b.addPolygon("white", faces[i], "open");
  const PosedScene posed = b.pose();
  const ClosednessReport report = checkClosedness(b.scene(), posed);
  EXPECT_TRUE(report.objects[0].isClosed);
  EXPECT_FALSE(report.objects[1].isClosed);
  EXPECT_EQ(report.objects[1].openEdgeCount, 4);
  EXPECT_NEAR(report.objects[1].openEdgeLength, 4.0, 1e-12);
  EXPECT_FALSE(report.isSceneClosed);
}

TEST(Closedness, TJunctionsAreClosed) {
  // The cube's top face split into two halves: the side faces' top edges are matched by two
  // shorter edges each on two sides.
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  std::vector<Polygon3> faces = cube(0, 0, 0, 1);
  faces.erase(faces.begin() + 1);
  faces.push_back({{0, 0, 1}, {0.5, 0, 1}, {0.5, 1, 1}, {0, 1, 1}});
  faces.push_back({{0.5, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0.5, 1, 1}});
  for (const Polygon3& f : faces) b.addPolygon("white", f, "split");
  const PosedScene posed = b.pose();
  EXPECT_TRUE(checkClosedness(b.scene(), posed).isSceneClosed);
}

TEST(Closedness, FlippedFaceIsNotClosed) {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  std::vector<Polygon3> faces = cube(0, 0, 0, 1);
  std::reverse(faces[2].begin(), faces[2].end());
  for (const Polygon3& f : faces) b.addPolygon("white", f, "flipped");
  const PosedScene posed = b.pose();
  EXPECT_FALSE(checkClosedness(b.scene(), posed).isSceneClosed);
}

}  // namespace
}  // namespace penumbra
