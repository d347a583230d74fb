#include "penumbra/dm/edge_adjacency.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

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

// Coincident copies of one polygon (a model's double-sided panel: the same corners, in the same or
// the reverse order) lie on the same side of each shared edge: knife edges that light grazes, not
// a flat region. Treated as flat, their corners generated no vertex events and the mesh missed
// the panel's shadow corners (fuzz findings mismatch-coincident-*: up to 23% off).
TEST(EdgeAdjacency, CoincidentCopiesOfAPolygonKeepTheirOutline) {
  for (const bool reversed : {false, true}) {
    test::SceneBuilder b;
    b.addMaterial("white", {0.5, 0.5, 0.5});
    Polygon3 card{{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    b.addPolygon("white", card, "front");
    if (reversed) std::reverse(card.begin(), card.end());
    b.addPolygon("white", card, "back");
    const PosedScene scene = b.pose();
    const EdgeAdjacency adjacency(scene);
    ASSERT_EQ(adjacency.edges().size(), 4u);
    for (const SceneEdge& e : adjacency.edges()) {
      EXPECT_EQ(e.polygons.size(), 2u);
      EXPECT_TRUE(e.canBeSilhouette) << (reversed ? "reversed" : "same order");
      // Seen from below, both copies lie on one side of the plane through the point and the edge.
      EXPECT_TRUE(adjacency.isSilhouetteFrom(EdgeId(&e - adjacency.edges().data()), {0.5, 0.5, 0}));
    }
    for (size_t v = 0; v < adjacency.vertices().size(); ++v)
      EXPECT_TRUE(adjacency.canVertexBeSilhouette(VertexId(v)));
  }
}

// The side a polygon takes beside an edge is its interior's there, not that of whichever vertex
// is off the edge's line: a non-convex polygon has vertices on both sides (the dm_geometry fuzzer's
// `mismatch-ramp-piercing-floor-beside-a-concave-pentagon`, where a ramp's shadow was lost).
TEST(EdgeAdjacency, ConcavePolygonLiesOnItsInteriorsSideOfAnEdge) {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  // Counter-clockwise about +z, its interior beside edge (0,0)-(1,0) on +y; it starts, and reaches
  // farthest, on -y.
  b.addPolygon(
      "white",
      {{-1, -3, 0}, {-0.2, -3, 0}, {-0.2, -0.1, 0}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 1, 0}},
      "hook");
  // A ramp from the same edge, down towards +y.
  b.addPolygon("white", {{1, 0, 0}, {0, 0, 0}, {0, 1, -1}, {1, 1, -1}}, "ramp");
  const PosedScene scene = b.pose();
  const EdgeAdjacency adjacency(scene);
  const auto shared = std::find_if(adjacency.edges().begin(), adjacency.edges().end(),
                                   [](const SceneEdge& e) { return e.polygons.size() == 2; });
  ASSERT_NE(shared, adjacency.edges().end());
  const EdgeId edge = EdgeId(shared - adjacency.edges().begin());
  // From above both lie on one side of the plane through the edge: the edge bounds what is seen.
  EXPECT_TRUE(adjacency.isSilhouetteFrom(edge, {0.5, 0.5, 5}));
  EXPECT_TRUE(adjacency.isSilhouetteFrom(edge, {0.5, -4, 5}));
  // From beyond the ramp, low, the plane passes between them: one face seen from each side.
  EXPECT_FALSE(adjacency.isSilhouetteFrom(edge, {0.5, 5, -0.3}));
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

// unchangedTopology, checked independently: data of the same id in both adjacencies compared
// directly.
bool sameVertexData(const EdgeAdjacency& before, const EdgeAdjacency& now, VertexId v) {
  if (size_t(v) >= before.vertices().size()) return false;
  const SceneVertex &a = before.vertices()[v], &b = now.vertices()[v];
  return a.position == b.position && a.edges == b.edges && a.polygons == b.polygons &&
         before.canVertexBeSilhouette(v) == now.canVertexBeSilhouette(v);
}

bool sameEdgeData(const EdgeAdjacency& before, const EdgeAdjacency& now, EdgeId e) {
  if (size_t(e) >= before.edges().size()) return false;
  const SceneEdge &a = before.edges()[e], &b = now.edges()[e];
  return a.a == b.a && a.b == b.b && a.polygons == b.polygons &&
         a.canBeSilhouette == b.canBeSilhouette && before.position(a.a) == now.position(b.a) &&
         before.position(a.b) == now.position(b.b);
}

bool samePolygonData(const EdgeAdjacency& before, const EdgeAdjacency& now, PolygonId p) {
  if (size_t(p) >= before.polygonCount()) return false;
  const std::vector<VertexId>& corners = now.polygonVertices(p);
  if (corners != before.polygonVertices(p)) return false;
  for (size_t k = 0; k < corners.size(); ++k) {
    const VertexId u = corners[k], w = corners[(k + 1) % corners.size()];
    if (!sameVertexData(before, now, u)) return false;
    const EdgeId e = now.edgeBetween(u, w);
    if (e != before.edgeBetween(u, w)) return false;
    if (e >= 0 && !sameEdgeData(before, now, e)) return false;
  }
  return true;
}

struct FlagCounts {
  int same = 0, changed = 0;
};

// Every flag is sized like `now`, and every "same" flag is confirmed by the data.
FlagCounts expectSameFlagsAreTrue(const EdgeAdjacency& before, const EdgeAdjacency& now,
                                  const UnchangedTopology& same) {
  FlagCounts counts;
  EXPECT_EQ(same.vertices.size(), now.vertices().size());
  EXPECT_EQ(same.edges.size(), now.edges().size());
  EXPECT_EQ(same.polygons.size(), now.polygonCount());
  for (size_t v = 0; v < same.vertices.size(); ++v) {
    (same.vertices[v] ? counts.same : counts.changed) += 1;
    if (same.vertices[v]) {
      EXPECT_TRUE(sameVertexData(before, now, VertexId(v)))
          << "vertex " << v << " at " << now.position(VertexId(v));
    }
  }
  for (size_t e = 0; e < same.edges.size(); ++e) {
    (same.edges[e] ? counts.same : counts.changed) += 1;
    if (same.edges[e]) {
      EXPECT_TRUE(sameEdgeData(before, now, EdgeId(e))) << "edge " << e;
    }
  }
  for (size_t p = 0; p < same.polygons.size(); ++p) {
    (same.polygons[p] ? counts.same : counts.changed) += 1;
    if (same.polygons[p]) {
      EXPECT_TRUE(samePolygonData(before, now, PolygonId(p))) << "polygon " << p;
    }
  }
  return counts;
}

// The scene with `object` moved by `by` from where `base` has it.
PosedScene translated(const Scene& scene, const PosedScene& base, int object, const Vec3& by) {
  std::vector<Transform> transforms = base.objectTransforms;
  transforms[object].translation += by;
  return poseWith(scene, transforms, base.extent, base.frame);
}

bool isObjectPolygon(const PosedScene& scene, int object, PolygonId p) {
  return p >= scene.objectFirstPolygon[object] && p < scene.objectFirstPolygon[object + 1];
}

// Two unit boxes, a lone quad, a square split into two triangles (a flat diagonal), a lone
// triangle: objects 0 to 4, apart from each other.
test::SceneBuilder separateObjects() {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  test::addBox(b, "white", "left box", {0, 0, 0}, {1, 1, 1});
  b.addPolygon("white", {{3, 0, 0}, {4, 0, 0}, {4, 1, 0.5}, {3, 1, 0.5}}, "quad");
  test::addBox(b, "white", "right box", {6, 0, 0}, {7, 1, 2});
  b.addPolygon("white", {{0, 3, 0}, {1, 3, 0}, {1, 4, 0}}, "sheet");
  b.addPolygon("white", {{0, 3, 0}, {1, 4, 0}, {0, 4, 0}}, "sheet");
  b.addPolygon("white", {{3, 3, 1}, {4, 3, 1}, {3.5, 4, 2}}, "triangle");
  return b;
}

TEST(UnchangedTopology, IdenticalScenesAreUnchanged) {
  const test::SceneBuilder b = separateObjects();
  const PosedScene first = b.pose(), second = b.pose();
  const EdgeAdjacency before(first), now(second), self(first);
  for (const EdgeAdjacency* other : {&now, &self}) {
    const UnchangedTopology same = unchangedTopology(before, *other);
    const FlagCounts counts = expectSameFlagsAreTrue(before, *other, same);
    EXPECT_EQ(counts.changed, 0);
    EXPECT_EQ(same.vertices, std::vector<char>(before.vertices().size(), 1));
    EXPECT_EQ(same.edges, std::vector<char>(before.edges().size(), 1));
    EXPECT_EQ(same.polygons, std::vector<char>(before.polygonCount(), 1));
  }
}

TEST(UnchangedTopology, MovingOneObjectChangesExactlyItsVerticesEdgesAndPolygons) {
  test::SceneBuilder b = separateObjects();
  const PosedScene start = b.pose();
  const EdgeAdjacency before(start);
  ASSERT_EQ(start.objectCount(), 5);
  for (int object = 0; object < start.objectCount(); ++object) {
    // Up and away from everything: no vertex comes to coincide with another.
    const PosedScene moved = translated(b.scene(), start, object, {0.25, 0.5, 5});
    const EdgeAdjacency now(moved);
    ASSERT_EQ(now.vertices().size(), before.vertices().size());
    ASSERT_EQ(now.edges().size(), before.edges().size());
    const UnchangedTopology same = unchangedTopology(before, now);
    expectSameFlagsAreTrue(before, now, same);
    // A vertex or edge belongs to the moved object when one of its polygons does (the objects are
    // apart, so all of them do).
    const auto moves = [&](const std::vector<PolygonId>& polygons) {
      return isObjectPolygon(moved, object, polygons.front());
    };
    for (size_t v = 0; v < same.vertices.size(); ++v)
      EXPECT_EQ(same.vertices[v] != 0, !moves(now.vertices()[v].polygons))
          << "object " << object << " vertex " << v;
    for (size_t e = 0; e < same.edges.size(); ++e)
      EXPECT_EQ(same.edges[e] != 0, !moves(now.edges()[e].polygons))
          << "object " << object << " edge " << e;
    for (size_t p = 0; p < same.polygons.size(); ++p)
      EXPECT_EQ(same.polygons[p] != 0, !isObjectPolygon(moved, object, PolygonId(p)))
          << "object " << object << " polygon " << p;
  }
}

// A box moved so that one of its corners lands exactly on a corner of a static box: the two
// vertices weld into one, and the ids of the vertices created after it shift.
void checkWeldAtCorner(bool staticFirst) {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  const auto addStatic = [&] { test::addBox(b, "white", "static", {0, 0, 0}, {1, 1, 1}); };
  const auto addMover = [&] { test::addBox(b, "white", "mover", {3, 0, 0}, {4, 1, 1}); };
  if (staticFirst) {
    addStatic();
    addMover();
  } else {
    addMover();
    addStatic();
  }
  const int staticObject = staticFirst ? 0 : 1, mover = 1 - staticObject;
  const PosedScene apart = b.pose();
  const PosedScene welded = translated(b.scene(), apart, mover, {-2, 1, 1});  // to [1, 2]^3
  const EdgeAdjacency before(apart), now(welded);
  ASSERT_EQ(before.vertices().size(), 16u);
  ASSERT_EQ(now.vertices().size(), 15u);
  const Vec3 corner{1, 1, 1};
  const UnchangedTopology same = unchangedTopology(before, now);
  const FlagCounts counts = expectSameFlagsAreTrue(before, now, same);
  for (size_t p = 0; p < same.polygons.size(); ++p) {
    const Polygon3& vertices = welded.polygons[p].vertices;
    const bool atCorner = std::find(vertices.begin(), vertices.end(), corner) != vertices.end();
    if (isObjectPolygon(welded, mover, PolygonId(p)) || atCorner) {
      EXPECT_FALSE(same.polygons[p]) << "polygon " << p;
    } else if (staticFirst) {  // the static box's ids are those of before
      EXPECT_TRUE(same.polygons[p]) << "polygon " << p;
    }
  }
  for (size_t v = 0; v < same.vertices.size(); ++v) {
    if (now.position(VertexId(v)) == corner) {
      EXPECT_FALSE(same.vertices[v]);
    }
  }
  if (staticFirst) {
    // Only the welded corner and the mover changed: the static box's 3 other faces, 7 other
    // corners and 12 edges are the same.
    EXPECT_EQ(counts.same, 3 + 7 + 12);
  }
  // Separating them again (the comparison the other way round).
  const UnchangedTopology back = unchangedTopology(now, before);
  expectSameFlagsAreTrue(now, before, back);
  for (size_t p = 0; p < back.polygons.size(); ++p) {
    const Polygon3& vertices = apart.polygons[p].vertices;
    if (std::find(vertices.begin(), vertices.end(), corner) != vertices.end()) {
      EXPECT_FALSE(back.polygons[p]) << "polygon " << p;
    }
  }
}

TEST(UnchangedTopology, WeldingAVertexChangesTheStaticPolygonsAtIt) {
  {
    SCOPED_TRACE("static box first");
    checkWeldAtCorner(true);
  }
  {
    SCOPED_TRACE("moving box first: the static box's vertex ids shift");
    checkWeldAtCorner(false);
  }
}

TEST(UnchangedTopology, WeldingEdgesAndFacesChangesThemAndTheirSilhouetteCapability) {
  // A static box with a square of two triangles on the plane of its top face; a box and a flat
  // quad (in that plane) that move next to them, sharing faces, edges or corners.
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  test::addBox(b, "white", "static", {0, 0, 0}, {1, 1, 1});
  b.addPolygon("white", {{1, 0, 1}, {2, 0, 1}, {2, 1, 1}}, "sheet");
  b.addPolygon("white", {{1, 0, 1}, {2, 1, 1}, {1, 1, 1}}, "sheet");
  test::addBox(b, "white", "box", {5, 0, 0}, {6, 1, 1});
  b.addPolygon("white", {{5, 3, 1}, {6, 3, 1}, {6, 4, 1}, {5, 4, 1}}, "quad");
  const PosedScene start = b.pose();
  const EdgeAdjacency before(start);
  const int box = 2, quad = 3;
  const std::pair<int, Vec3> moves[] = {
      {box, {-4, 0, 0}},   {box, {-3, 0, 0}},  {box, {-3, 0, 1}},   {box, {-4, 0, 1}},
      {box, {-5, 0, 0}},   {box, {-4, 1, 0}},  {quad, {-3, -3, 0}}, {quad, {-4, -3, 0}},
      {quad, {-5, -2, 0}}, {quad, {-4, -2, 0}}};
  for (const auto& [object, by] : moves) {
    const PosedScene moved = translated(b.scene(), start, object, by);
    const EdgeAdjacency now(moved);
    SCOPED_TRACE(testing::Message() << "object " << object << " moved by " << by);
    const UnchangedTopology same = unchangedTopology(before, now);
    const FlagCounts counts = expectSameFlagsAreTrue(before, now, same);
    EXPECT_GT(counts.changed, 0);
    EXPECT_GT(counts.same, 0);
    // The moved polygons always change, and so does every other polygon with a corner on one of
    // their corners.
    std::vector<Vec3> movedCorners;
    for (PolygonId p = moved.objectFirstPolygon[object]; p < moved.objectFirstPolygon[object + 1];
         ++p) {
      EXPECT_FALSE(same.polygons[p]) << "polygon " << p;
      for (const Vec3& corner : moved.polygons[p].vertices) movedCorners.push_back(corner);
    }
    for (PolygonId p = 0; p < PolygonId(moved.polygons.size()); ++p) {
      const Polygon3& corners = moved.polygons[p].vertices;
      const bool touches = std::any_of(corners.begin(), corners.end(), [&](const Vec3& c) {
        return std::find(movedCorners.begin(), movedCorners.end(), c) != movedCorners.end();
      });
      if (touches) {
        EXPECT_FALSE(same.polygons[p]) << "polygon " << p;
      }
    }
  }
  // The quad moved to share the square's edge x = 2 in its plane: that edge joins two coplanar
  // polygons and can no longer be a silhouette; it, its ends and the triangle are not the same.
  const PosedScene moved = translated(b.scene(), start, quad, {-3, -3, 0});
  const EdgeAdjacency now(moved);
  const UnchangedTopology same = unchangedTopology(before, now);
  const auto vertexAt = [](const EdgeAdjacency& adjacency, const Vec3& p) {
    for (size_t v = 0; v < adjacency.vertices().size(); ++v)
      if (adjacency.position(VertexId(v)) == p) return VertexId(v);
    return VertexId(-1);
  };
  const Vec3 p{2, 0, 1}, q{2, 1, 1};
  const EdgeId edgeBefore = before.edgeBetween(vertexAt(before, p), vertexAt(before, q));
  const EdgeId edgeNow = now.edgeBetween(vertexAt(now, p), vertexAt(now, q));
  ASSERT_GE(edgeBefore, 0);
  ASSERT_GE(edgeNow, 0);
  EXPECT_TRUE(before.edges()[edgeBefore].canBeSilhouette);
  EXPECT_FALSE(now.edges()[edgeNow].canBeSilhouette);
  EXPECT_FALSE(same.edges[edgeNow]);
  EXPECT_FALSE(same.vertices[vertexAt(now, p)]);
  EXPECT_FALSE(same.vertices[vertexAt(now, q)]);
  EXPECT_FALSE(same.polygons[6]);  // the square's first triangle, which has that edge
  EXPECT_TRUE(same.polygons[0]);   // the static box's bottom face, away from everything
}

TEST(UnchangedTopology, RandomLatticeMovesNeverClaimAChangedElementIsTheSame) {
  // Objects on an integer lattice moved by integer steps: vertices, edges and faces often come to
  // coincide (welding and unwelding, edges gaining and losing polygons, flat edges becoming
  // folds), and the ids after them shift.
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  test::addBox(b, "white", "a", {0, 0, 0}, {1, 1, 1});
  b.addPolygon("white", {{1, 0, 0}, {2, 0, 0}, {2, 1, 0}}, "sheet");
  b.addPolygon("white", {{1, 0, 0}, {2, 1, 0}, {1, 1, 0}}, "sheet");
  test::addBox(b, "white", "b", {2, 0, 0}, {3, 1, 2});
  b.addPolygon("white", {{0, 2, 0}, {1, 2, 0}, {1, 2, 1}, {0, 2, 1}}, "quad");
  test::addBox(b, "white", "c", {0, 0, 1}, {2, 1, 2});
  std::vector<PosedScene> frames;
  frames.reserve(301);
  frames.push_back(b.pose());
  std::mt19937 rng(77);
  std::uniform_int_distribution<int> anyObject(0, frames[0].objectCount() - 1), step(-1, 1);
  for (int i = 0; i < 300; ++i) {
    const int object = anyObject(rng);
    Vec3 by{double(step(rng)), double(step(rng)), double(step(rng))};
    // Keep every object near the others.
    const Vec3 at = frames.back().objectTransforms[object].translation + by;
    for (int k = 0; k < 3; ++k)
      if (std::abs(at[k]) > 2) by[k] = -by[k];
    frames.push_back(translated(b.scene(), frames.back(), object, by));
  }
  FlagCounts total;
  int vertexCountChanges = 0;
  std::vector<EdgeAdjacency> adjacencies;
  adjacencies.reserve(frames.size());
  for (const PosedScene& frame : frames) adjacencies.emplace_back(frame);
  for (size_t i = 1; i < frames.size(); ++i) {
    SCOPED_TRACE(testing::Message() << "frame " << i);
    const EdgeAdjacency &before = adjacencies[i - 1], &now = adjacencies[i];
    const FlagCounts counts = expectSameFlagsAreTrue(before, now, unchangedTopology(before, now));
    total.same += counts.same;
    total.changed += counts.changed;
    vertexCountChanges += before.vertices().size() != now.vertices().size() ? 1 : 0;
    // And between frames further apart.
    if (i >= 5)
      expectSameFlagsAreTrue(adjacencies[i - 5], now, unchangedTopology(adjacencies[i - 5], now));
  }
  // Not vacuous: much is kept, much changes, and vertices often weld or separate.
  EXPECT_GT(total.same, 1000);
  EXPECT_GT(total.changed, 1000);
  EXPECT_GT(vertexCountChanges, 30);
}

}  // namespace
}  // namespace penumbra
