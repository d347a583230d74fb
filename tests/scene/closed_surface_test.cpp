#include "penumbra/scene/closed_surface.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "support/boxes.h"

namespace penumbra {
namespace {

using test::boxFaces;

std::vector<int> surfacesOf(const std::vector<Polygon3>& polygons) {
  std::vector<const Polygon3*> rings;
  for (const Polygon3& p : polygons) rings.push_back(&p);
  return closedSurfaces(rings);
}

Polygon3 reversed(Polygon3 p) {
  std::reverse(p.begin(), p.end());
  return p;
}

TEST(ClosedSurface, ABoxIsOneClosedSurface) {
  EXPECT_EQ(surfacesOf(boxFaces({0, 0, 0}, {1, 2, 3})), std::vector<int>(6, 0));
}

TEST(ClosedSurface, ABoxTurnedInsideOutIsClosedToo) {
  std::vector<Polygon3> faces = boxFaces({0, 0, 0}, {1, 1, 1});
  for (Polygon3& f : faces) f = reversed(f);
  EXPECT_EQ(surfacesOf(faces), std::vector<int>(6, 0));
}

TEST(ClosedSurface, BoxesOfOnePieceOfFurnitureAreNumberedApart) {
  // A box standing on another (its bottom on the other's top, no corner shared), then an open
  // card: surfaces 0 and 1, the card -1.
  std::vector<Polygon3> faces = boxFaces({0, 0, 0}, {1, 1, 1});
  for (const Polygon3& f : boxFaces({0.25, 0.25, 1}, {0.75, 0.75, 2})) faces.push_back(f);
  faces.push_back({{3, 0, 0}, {4, 0, 0}, {4, 1, 0}});
  std::vector<int> expected(6, 0);
  expected.insert(expected.end(), 6, 1);
  expected.push_back(-1);
  EXPECT_EQ(surfacesOf(faces), expected);
}

TEST(ClosedSurface, ATwoSidedCardIsClosed) {
  // Its two polygons run every edge once each way: a surface of no volume, which a segment
  // crosses through both of them.
  const Polygon3 card{{0, 0, 0}, {1, 0, 0}, {0, 1, 0.5}};
  EXPECT_EQ(surfacesOf({card, reversed(card)}), (std::vector<int>{0, 0}));
}

TEST(ClosedSurface, AMissingFaceOpensIt) {
  std::vector<Polygon3> faces = boxFaces({0, 0, 0}, {1, 1, 1});
  faces.pop_back();
  EXPECT_EQ(surfacesOf(faces), std::vector<int>(5, -1));
}

TEST(ClosedSurface, OneFaceTurnedTheWrongWayOpensIt) {
  std::vector<Polygon3> faces = boxFaces({0, 0, 0}, {1, 1, 1});
  faces[2] = reversed(faces[2]);
  EXPECT_EQ(surfacesOf(faces), std::vector<int>(6, -1));
}

TEST(ClosedSurface, ACornerOneUlpAwayOpensIt) {
  std::vector<Polygon3> faces = boxFaces({0, 0, 0}, {1, 1, 1});
  faces[1][2].x = std::nextafter(1.0, 2.0);
  EXPECT_EQ(surfacesOf(faces), std::vector<int>(6, -1));
}

TEST(ClosedSurface, ATJunctionOpensIt) {
  // The top split in two halves: the side faces' top edges meet two half-edges each, not one.
  std::vector<Polygon3> faces = boxFaces({0, 0, 0}, {2, 1, 1});
  faces[1] = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  faces.push_back({{1, 0, 1}, {2, 0, 1}, {2, 1, 1}, {1, 1, 1}});
  EXPECT_EQ(surfacesOf(faces), std::vector<int>(7, -1));
}

TEST(ClosedSurface, BoxesStackedCornerToCornerAreOpen) {
  // The top of one is the bottom of the other, corners and all: every edge of that square is run
  // by four polygons.
  std::vector<Polygon3> faces = boxFaces({0, 0, 0}, {1, 1, 1});
  for (const Polygon3& f : boxFaces({0, 0, 1}, {1, 1, 2})) faces.push_back(f);
  EXPECT_EQ(surfacesOf(faces), std::vector<int>(12, -1));
}

TEST(ClosedSurface, AnEdgeSharedByFourPolygonsOpensIt) {
  // Two boxes along one edge only (x = 1, y = 1): that edge is run twice each way.
  std::vector<Polygon3> faces = boxFaces({0, 0, 0}, {1, 1, 1});
  for (const Polygon3& f : boxFaces({1, 1, 0}, {2, 2, 1})) faces.push_back(f);
  EXPECT_EQ(surfacesOf(faces), std::vector<int>(12, -1));
}

TEST(ClosedSurface, RepeatedCornersAreEdgesOfNoLength) {
  std::vector<Polygon3> faces = boxFaces({0, 0, 0}, {1, 1, 1});
  faces[0].insert(faces[0].begin() + 1, faces[0][1]);
  EXPECT_EQ(surfacesOf(faces), std::vector<int>(6, 0));
}

}  // namespace
}  // namespace penumbra
