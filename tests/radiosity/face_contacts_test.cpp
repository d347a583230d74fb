// Which coplanar polygons cover which (coveringPolygons): contacts of solids, the two sides of a
// sheet, polygons lying on one another facing the same way.

#include "penumbra/radiosity/face_contacts.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "support/boxes.h"

namespace penumbra {
namespace {

bool covers(const std::vector<std::vector<PolygonId>>& covering, PolygonId covered, PolygonId by) {
  const auto& list = covering[size_t(covered)];
  return std::find(list.begin(), list.end(), by) != list.end();
}

TEST(CoveringPolygons, SolidsInContactSheetsAndLayers) {
  test::SceneBuilder b;
  b.addMaterial("white", Rgb::gray(0.5)).addMaterial("lamp", Rgb::gray(0), Rgb::gray(10));
  test::addRoom(b, "white", {0, 0, 0}, {2, 2, 2});  // 0-5; the floor is 2, the ceiling 3
  // A chair's leg: a box open at the top, where it meets the seat (6-10, its bottom 8).
  std::vector<Polygon3> leg = test::boxFaces({0.2, 0, 0.2}, {0.25, 0.4, 0.25});
  leg.erase(leg.begin() + 3);
  for (const Polygon3& f : leg) b.addPolygon("white", f, "chair");
  test::addBox(b, "white", "chair", {0.15, 0.4, 0.15}, {0.6, 0.45, 0.6});  // the seat: 11-16
  // Two slabs stacked (17-22, 23-28): the lower's top (20) under the upper's bottom (25).
  test::addBox(b, "white", "slabs", {1, 0, 1}, {1.3, 0.1, 1.3});
  test::addBox(b, "white", "slabs", {1, 0.1, 1}, {1.3, 0.2, 1.3});
  // A two-sided card standing in the room (29, 30).
  const Polygon3 card{{1.6, 0.5, 0.5}, {1.6, 1.5, 0.5}, {1.6, 1.5, 1.5}, {1.6, 0.5, 1.5}};
  b.addPolygon("white", card, "card");
  b.addPolygon("white", {card[3], card[2], card[1], card[0]}, "card");
  // A rug on the floor (31), and a lamp in the ceiling's plane listed last (32).
  b.addPolygon("white", {{0.8, 0, 1.5}, {0.8, 0, 1.9}, {1.9, 0, 1.9}, {1.9, 0, 1.5}}, "rug");
  b.addPolygon("lamp", {{0.9, 2, 0.9}, {1.1, 2, 0.9}, {1.1, 2, 1.1}, {0.9, 2, 1.1}}, "lamp");
  const PosedScene scene = b.pose();
  ASSERT_EQ(scene.polygons.size(), 33u);
  const auto covering = coveringPolygons(scene);
  EXPECT_TRUE(covers(covering, 2, 8) && covers(covering, 8, 2));      // the leg on the floor
  EXPECT_TRUE(covers(covering, 20, 25) && covers(covering, 25, 20));  // stacked slabs
  EXPECT_TRUE(covers(covering, 2, 19) && covers(covering, 19, 2));    // the lower slab's bottom
  EXPECT_TRUE(covering[29].empty() && covering[30].empty());          // the card's two sides
  EXPECT_TRUE(covers(covering, 2, 31) && covering[31].empty());       // the rug lies on top
  EXPECT_TRUE(covers(covering, 3, 32) && covering[32].empty());       // so does the lamp
}

}  // namespace
}  // namespace penumbra
