#include "penumbra/dm/edge_adjacency.h"

#include <gtest/gtest.h>

#include "support/boxes.h"

namespace penumbra {
namespace {

TEST(EdgeAdjacency, CubeHasTwelveManifoldEdges) {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  test::addBox(b, "white", "cube", {0, 0, 0}, {1, 1, 1});
  const PosedScene scene = b.pose();
  const EdgeAdjacency adjacency(scene);
  EXPECT_EQ(adjacency.vertices().size(), 8u);
  ASSERT_EQ(adjacency.edges().size(), 12u);
  for (const SceneEdge& e : adjacency.edges()) {
    EXPECT_EQ(e.polygons.size(), 2u);
    EXPECT_TRUE(e.canBeSilhouette);
  }
}

TEST(EdgeAdjacency, SilhouettesSeenFromAbove) {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  test::addBox(b, "white", "cube", {0, 0, 0}, {1, 1, 1});
  const PosedScene scene = b.pose();
  const EdgeAdjacency adjacency(scene);
  const Vec3 above{0.5, 0.5, 5};  // sees the top face only
  int silhouettes = 0;
  for (size_t e = 0; e < adjacency.edges().size(); ++e) {
    const SceneEdge& edge = adjacency.edges()[e];
    const bool isTopEdge = adjacency.position(edge.a).z == 1 && adjacency.position(edge.b).z == 1;
    EXPECT_EQ(adjacency.isSilhouetteFrom(EdgeId(e), above), isTopEdge) << e;
    silhouettes += adjacency.isSilhouetteFrom(EdgeId(e), above) ? 1 : 0;
  }
  EXPECT_EQ(silhouettes, 4);
  // From a corner direction the silhouette is the six-edge outline.
  silhouettes = 0;
  for (size_t e = 0; e < adjacency.edges().size(); ++e)
    silhouettes += adjacency.isSilhouetteFrom(EdgeId(e), {5, 6, 7}) ? 1 : 0;
  EXPECT_EQ(silhouettes, 6);
}

TEST(EdgeAdjacency, TriangulatedQuadDiagonalIsNeverASilhouette) {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  b.addPolygon("white", {{0, 0, 0}, {1, 0, 0.5}, {1, 1, 0.5}}, "quad");
  b.addPolygon("white", {{0, 0, 0}, {1, 1, 0.5}, {0, 1, 0}}, "quad");
  const PosedScene scene = b.pose();
  const EdgeAdjacency adjacency(scene);
  int flat = 0;
  for (const SceneEdge& e : adjacency.edges()) flat += e.canBeSilhouette ? 0 : 1;
  EXPECT_EQ(flat, 1);
  EXPECT_EQ(adjacency.edges().size(), 5u);
  // Every vertex is a corner of the quad, so each can generate events.
  for (size_t v = 0; v < adjacency.vertices().size(); ++v)
    EXPECT_TRUE(adjacency.canVertexBeSilhouette(VertexId(v)));
}

TEST(EdgeAdjacency, VertexInsideAFlatRegionIsNotAFeature) {
  // Four coplanar quads around the origin: the centre vertex is interior, the others are corners
  // or boundary points.
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      const double x = i - 1.0, y = j - 1.0;
      b.addPolygon("white", {{x, y, 0}, {x + 1, y, 0}, {x + 1, y + 1, 0}, {x, y + 1, 0}}, "floor");
    }
  const PosedScene scene = b.pose();
  const EdgeAdjacency adjacency(scene);
  for (size_t v = 0; v < adjacency.vertices().size(); ++v)
    EXPECT_EQ(adjacency.canVertexBeSilhouette(VertexId(v)),
              !(adjacency.position(VertexId(v)) == Vec3{0, 0, 0}));
}

}  // namespace
}  // namespace penumbra
