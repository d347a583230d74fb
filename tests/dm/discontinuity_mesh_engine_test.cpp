// The discontinuity-mesh engine against the exact reference (independent: polygon booleans of the
// light minus every occluder's projection, per point, no mesh): at random receiver points, the
// irradiance from the located face's backprojection equals the reference to 1e-9 relative.

#include "penumbra/dm/discontinuity_mesh_engine.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>

#include "penumbra/dm/irradiance_mesh.h"
#include "penumbra/geometry/quaternion.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/scene/receiver_sampling.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/receiver_locator.h"
#include "support/boxes.h"

namespace penumbra {
namespace {

// A closed 4 x 4 x 3 room with a 1 x 1 light just below the ceiling.
test::SceneBuilder litRoom() {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5}).addMaterial("lamp", {0, 0, 0}, {10, 10, 10});
  test::addRoom(b, "white", {0, 0, 0}, {4, 4, 3});
  b.addPolygon("lamp", {{1.5, 1.5, 2.9}, {1.5, 2.5, 2.9}, {2.5, 2.5, 2.9}, {2.5, 1.5, 2.9}});
  return b;
}

// A 0.5 m square light facing down at y = 2 over a 4 x 4 floor (y up), polygons 0 (the floor)
// and 1: the degenerate scenes of session 31 (docs/shadows.md).
test::SceneBuilder smallLampOverFloor() {
  test::SceneBuilder b;
  b.addMaterial("white", {0.7, 0.7, 0.7}).addMaterial("lamp", {0, 0, 0}, {10, 10, 10});
  b.addPolygon("white", {{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}, "floor");
  b.addPolygon("lamp", {{-0.25, 2, -0.25}, {0.25, 2, -0.25}, {0.25, 2, 0.25}, {-0.25, 2, 0.25}},
               "lamp");
  return b;
}

struct Comparison {
  int points = 0, failures = 0;
  int answeredByMesh = 0;  // the rest were answered at the point (by the exact reference)
  double worst = 0;
  std::string firstFailure;
};

Comparison compareWithReference(const PosedScene& scene, int count, std::uint64_t seed,
                                DmOptions options = {}) {
  DiscontinuityMeshEngine engine(options);
  engine.build(PosedScene(scene));
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  Comparison c;
  for (const ReceiverPoint& q : sampleReceiverPoints(scene, count, seed)) {
    const Rgb expected = reference.irradiance(q.p, q.n, q.receiver);
    // Only what the mesh answers is compared: a point the engine answers at the point is the
    // reference's own value and says nothing (the fallback is counted, not trusted).
    const auto query = engine.query(q.p, q.n);
    ++c.points;
    if (query && query->answer != DiscontinuityMeshEngine::Answer::kMesh) continue;
    ++c.answeredByMesh;
    const std::optional<Rgb> got = query ? std::optional(query->irradiance) : std::nullopt;
    // Relative to the value; in the umbra (0) relative to the light's exitance (10), times 1e-12.
    const double scale = std::max(1e-11, expected.maxComponent());
    const double error = got ? std::abs(got->r - expected.r) / scale : INFINITY;
    c.worst = std::max(c.worst, error);
    if (!(error <= 1e-9)) {
      if (c.failures++ == 0)
        c.firstFailure = "at (" + std::to_string(q.p.x) + ", " + std::to_string(q.p.y) + ", " +
                         std::to_string(q.p.z) + ") on polygon " + std::to_string(q.receiver) +
                         ": dm " + (got ? std::to_string(got->r) : "none") + ", reference " +
                         std::to_string(expected.r);
    }
  }
  return c;
}

// The mesh's completeness, checked against the reference: faces whose sample's labels give a
// wrong irradiance just inside one of their corners (a missing event crosses them). Corners
// beside an EEE polyline are left out (the polyline stands within its tolerance of the conic).
int facesWrongAtCorners(const PosedScene& scene, const std::string& what = "",
                        DmOptions options = {}) {
  options.verifyFaces = false;
  DiscontinuityMeshEngine engine(options);
  engine.build(PosedScene(scene));
  const UniformGrid grid(engine.posedScene());
  const ExactReference reference(engine.posedScene(), &grid);
  int wrong = 0;
  for (const WorldPolygon& receiver : engine.posedScene().polygons) {
    const ReceiverMesh* mesh = engine.meshOf(receiver.id);
    if (!mesh) continue;
    for (const MeshFace& face : mesh->faces()) {
      bool faceWrong = false;
      for (const Polygon3& cycle : mesh->faceBoundary(face.index))
        for (const Vec3& corner : cycle) {
          const Vec3 p =
              corner + (face.samplePoint - corner) * DiscontinuityMeshEngine::kCornerInsets.front();
          if (faceWrong || mesh->locate(p) != face.index ||
              engine.isNearEeePolyline(receiver.id, p))
            continue;
          const double expected = reference.irradiance(p, receiver.plane.normal, receiver.id).r;
          const double got = engine.faceIrradianceAt(receiver.id, face.index, p).r;
          faceWrong = std::abs(got - expected) > 1e-9 * std::max(1e-2, expected);
          if (faceWrong && wrong == 0 && !what.empty())
            ADD_FAILURE() << what << ": first face wrong at a corner on polygon " << receiver.id
                          << " at (" << p.x << ", " << p.y << ", " << p.z << "): mesh " << got
                          << ", reference " << expected;
        }
      wrong += faceWrong ? 1 : 0;
    }
  }
  return wrong;
}

// Every point the mesh answers equals the reference; at least `meshShare` of them are answered
// by the mesh (the engine answers the rest at the point: unresolved and sliver faces, EEE
// polylines, degenerate corners).
void expectExact(const PosedScene& scene, int count, std::uint64_t seed, double meshShare = 0.995) {
  const Comparison c = compareWithReference(scene, count, seed);
  std::printf("[ info     ] %d of %d points answered by the mesh (%.2f%%)\n", c.answeredByMesh,
              c.points, 100.0 * c.answeredByMesh / c.points);
  EXPECT_EQ(c.failures, 0) << c.failures << " of " << c.answeredByMesh
                           << " points answered by the mesh differ by more than 1e-9 (worst "
                           << c.worst << "), first " << c.firstFailure;
  EXPECT_GE(c.answeredByMesh, meshShare * c.points);
}

// A bundled scene (a desk with chairs, shelves, books: contacts, slits between books, receivers
// whose planes cut the light).
TEST(DiscontinuityMeshEngine, Desk145IsExact) {
  const Scene scene =
      loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/office-desk/desk-145.json");
  expectExact(poseAt(scene, 0), 1500, 21);
}

// Face verification: without EEE surfaces the faces crossed by an EEE event are caught (their
// labels differ at a corner), and the answers there, computed at the point, stay exact; with the
// mesh answering from the sample's labels alone, some points are wrong. Two boxes turned about
// tilted axes, one above the other, give EEE events where their shadows overlap.
TEST(DiscontinuityMeshEngine, FaceVerificationCatchesFacesCrossedByMissingEvents) {
  test::SceneBuilder b = litRoom();
  test::addTiltedBoxPair(b, "white");
  const PosedScene scene = b.pose();
  DiscontinuityMeshEngine complete, withoutEee({.eeeSurfaces = false});
  complete.build(PosedScene(scene));
  withoutEee.build(PosedScene(scene));
  EXPECT_GT(complete.stats().surfacesEee, 0);
  EXPECT_GT(withoutEee.stats().unresolvedFaces, complete.stats().unresolvedFaces);
  expectExact(scene, 1500, 22);
  const Comparison verified =
      compareWithReference(scene, 3000, 23, {.eeeSurfaces = false, .verifyFaces = true});
  EXPECT_EQ(verified.failures, 0) << verified.firstFailure;
  const Comparison unverified =
      compareWithReference(scene, 3000, 23, {.eeeSurfaces = false, .verifyFaces = false});
  EXPECT_GT(unverified.failures, 0);
}

// Three thin strips at three heights, turned about the vertical by different angles: from floor
// points under them the crossing of two strips' projected edges passes over the third's inside the
// light, an EEE event of three occluder edges. Without those surfaces the faces they cross are
// caught by verification and the mesh alone is wrong there; with them the mesh alone is exact.
TEST(DiscontinuityMeshEngine, ThreeOccluderEdgeEventsCompleteTheMesh) {
  test::SceneBuilder b = litRoom();
  const auto addStrip = [&](double height, double angle, double dx) {
    const double c = std::cos(angle), s = std::sin(angle), halfLength = 1.2, halfWidth = 0.02;
    Polygon3 strip;
    for (const auto& [u, v] : {std::pair{-halfLength, -halfWidth},
                               {-halfLength, halfWidth},
                               {halfLength, halfWidth},
                               {halfLength, -halfWidth}})
      strip.push_back({2 + dx + u * c - v * s, 2 + u * s + v * c, height});
    b.addPolygon("white", strip);
  };
  addStrip(2.2, 0.3, 0.0);
  addStrip(1.7, -0.6, 0.1);
  addStrip(1.2, 1.3, -0.1);
  const PosedScene scene = b.pose();
  DiscontinuityMeshEngine complete, withoutThree({.occluderEeeSurfaces = false});
  complete.build(PosedScene(scene));
  withoutThree.build(PosedScene(scene));
  EXPECT_GT(complete.stats().surfacesEeeOccluder, 0);
  EXPECT_EQ(withoutThree.stats().surfacesEeeOccluder, 0);
  EXPECT_GT(withoutThree.stats().unresolvedFaces, complete.stats().unresolvedFaces);
  const Comparison meshAlone = compareWithReference(scene, 4000, 24, {.verifyFaces = false});
  EXPECT_EQ(meshAlone.failures, 0)
      << meshAlone.failures << " of " << meshAlone.points << ", first " << meshAlone.firstFailure;
  const Comparison meshAloneWithoutThree =
      compareWithReference(scene, 4000, 24, {.occluderEeeSurfaces = false, .verifyFaces = false});
  EXPECT_GT(meshAloneWithoutThree.failures, 0);
  expectExact(scene, 1500, 25);
}

// A polygon whose plane cuts the light is edge-on from that plane, and crossing the plane flips
// its projection over: where that projection lies inside the light's trace, its ends are at the
// polygon's vertices (SurfaceKind::kOccluderPlaneOccluderVertex). A box turned about a tilted
// axis close under the light (from the generated rotated-boxes scenes, seed 11): without those
// fans 4 faces were wrong at a corner (measured when they were added), with them none.
TEST(DiscontinuityMeshEngine, EdgeOnFacesFlippingInsideTheLightCompleteTheMesh) {
  test::SceneBuilder b;
  b.addMaterial("white", {0.6, 0.6, 0.6}).addMaterial("lamp", {0, 0, 0}, {10, 10, 10});
  test::addRoom(b, "white", {0, 0, 0}, {4, 3, 4});
  b.addPolygon("lamp", {{1.4, 2.95, 1.4}, {2.6, 2.95, 1.4}, {2.6, 2.95, 2.6}, {1.4, 2.95, 2.6}});
  const Quaternion turn = Quaternion::fromAxisAngle(normalize(Vec3{-0.0948971, 0.312442, 0.389085}),
                                                    155.493 * std::numbers::pi / 180);
  for (Polygon3 face :
       test::boxFaces({-0.102626, -0.0587862, -0.282503}, {0.102626, 0.0587862, 0.282503})) {
    for (Vec3& v : face) v = turn.toMatrix() * v + Vec3{1.48292, 1.8, 1.40649};
    b.addPolygon("white", face, "box");
  }
  const PosedScene scene = b.pose();
  DiscontinuityMeshEngine engine;
  engine.build(PosedScene(scene));
  EXPECT_GT(engine.stats().surfacesOccluderPlaneVertex, 0);
  EXPECT_EQ(facesWrongAtCorners(scene, "turned box"), 0);
}

// Two coplanar occluder edges of different objects (a desk's leg and a drawer front flush with
// it, books on a shelf): seen from their common plane their projections line up, and which one
// bounds the visible light switches (SurfaceKind::kLightEdgeCoplanarEdges). The bundled desk-145
// has such pairs; without those fans it had 2 faces wrong at a corner (measured when they were
// added), with them none.
TEST(DiscontinuityMeshEngine, CoplanarEdgesOfDifferentObjectsCompleteTheMesh) {
  const Scene scene =
      loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/office-desk/desk-145.json");
  DiscontinuityMeshEngine engine;
  engine.build(scene, 0);
  EXPECT_GT(engine.stats().surfacesCoplanarEdges, 0);
  EXPECT_EQ(facesWrongAtCorners(poseAt(scene, 0), "desk-145"), 0);
}

// Two parallel occluder edges of different objects (desk-307's desk top front edge and a drawer
// bottom's front edge) span a plane that crosses the lamp; seen from it their projections
// coincide. Two more edges (a leg's, a drawer side's) cross that plane and, with either of the
// two, bound a sliver of visible light on the floor: at the crossing of the third edge's
// projection with theirs the region's vertex switches from one edge to the other. Neither light
// edge's fan of the plane reaches that (kLightEdgeCoplanarEdges holds the lines through the
// trace's ends only): the fans through the crossings do (kCoplanarEdgesOccluderCrossing). Without
// them the floor's face there is unresolved (its labels (33,3)(44,1)(55,2) wrong at a corner
// where (7,2) takes over); with them the mesh answers there, exactly.
TEST(DiscontinuityMeshEngine, CoplanarEdgesCrossedByAnotherEdgeCompleteTheMesh) {
  const Scene scene =
      loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/office-desk/desk-307.json");
  DmOptions without;
  without.coplanarEdgeCrossings = false;
  DiscontinuityMeshEngine before(without);
  before.build(scene, 0);
  EXPECT_EQ(before.stats().unresolvedFaces, 1);
  DiscontinuityMeshEngine engine;
  engine.build(scene, 0);
  EXPECT_GT(engine.stats().surfacesCoplanarEdgeCrossing, 0);
  EXPECT_EQ(engine.stats().unresolvedFaces, 0);
  // Inside the face that was unresolved: answered by the mesh, as the reference.
  const Vec3 p{3.16594783, 0, 1.16594592}, up{0, 1, 0};
  const auto query = engine.query(p, up);
  ASSERT_TRUE(query);
  EXPECT_EQ(query->answer, DiscontinuityMeshEngine::Answer::kMesh);
  const double expected = engine.irradianceAtPoint(0, p).r;
  EXPECT_GT(expected, 0);
  EXPECT_NEAR(query->irradiance.r, expected, 1e-9 * expected);
}

// Points exactly on mesh edges (the middle of every edge an EV or EEE event made, not lying on a
// contact line, where irradiance jumps): the located face is either neighbour, and both give the
// reference's value (irradiance is continuous across those events).
// Bundled furnished scenes whose mesh is complete: no face's labels are wrong at any of its
// corners with face verification off. The chair room's and desk-307's last missing events were EV
// events lost where a visibility interval 1e-14 wide at a receiver segment's end took the segment's
// far end (fan_visibility.cpp; 4 and 6 faces wrong at a corner before that fix).
TEST(DiscontinuityMeshEngine, FurnishedScenesHaveCompleteMeshes) {
  for (const char* name :
       {"/scenes/chair-room/chair-room.json", "/scenes/office-desk/desk-307.json"}) {
    const Scene scene = loadScene(std::string(PENUMBRA_SOURCE_DIR) + name);
    EXPECT_EQ(facesWrongAtCorners(poseAt(scene, 0), name), 0) << name;
  }
}

// An occluder edge parallel to a light edge (a bar along x under a light with edges along x) lies
// in one plane with it; seen from that plane the bar's edge lines up with the light edge. Two
// blocks between them cross that plane, and from the floor beyond, the bar's edge is seen through
// the gap between them along lines that meet neither edge's ends: the event there is held only by
// the fans through the points where the blocks cross the plane (SurfaceKind::
// kLightEdgeParallelEdgeCrossing). Without them 4 faces are wrong at a corner; with them none
// (once each fan through X holds every polygon through X as a hinge: with only one, 2 were).
TEST(DiscontinuityMeshEngine, ParallelEdgesSeenPastObstaclesCompleteTheMesh) {
  test::SceneBuilder b = litRoom();
  // The bar's lower front edge (y 1.9, z 1.2) and the light's edge at y 1.5 share a plane that
  // crosses z 2.2 at y 1.665 and the floor at y 2.18; two blocks there hide the lines from the
  // light edge's ends to the floor's middle and leave a gap between them.
  test::addBox(b, "white", "bar", {1.2, 1.9, 1.2}, {2.8, 2.0, 1.3});
  test::addBox(b, "white", "left block", {1.55, 1.64, 2.1}, {1.8, 1.69, 2.3});
  test::addBox(b, "white", "right block", {2.2, 1.64, 2.1}, {2.45, 1.69, 2.3});
  const PosedScene scene = b.pose();
  DiscontinuityMeshEngine engine;
  engine.build(PosedScene(scene));
  EXPECT_GT(engine.stats().surfacesParallelEdgeCrossing, 0);
  EXPECT_EQ(facesWrongAtCorners(scene, "bar and blocks"), 0);
  EXPECT_GT(facesWrongAtCorners(scene, "", {.parallelEdgeCrossings = false}), 0);
}

TEST(DiscontinuityMeshEngine, PointsOnMeshEdgesAreExact) {
  test::SceneBuilder b = litRoom();
  test::addTiltedBoxPair(b, "white");
  test::addBox(b, "white", "resting", {0.6, 0.7, 0}, {1.1, 1.3, 0.5});
  const PosedScene scene = b.pose();
  DiscontinuityMeshEngine engine;
  engine.build(PosedScene(scene));
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  int checked = 0, failures = 0, byMesh = 0;
  for (const WorldPolygon& receiver : scene.polygons) {
    const ReceiverMesh* mesh = engine.meshOf(receiver.id);
    if (!mesh) continue;
    for (const auto& [segment, surfaces] : mesh->edges()) {
      // Surfaces of events have ids from 0; the outline, contact lines, light planes and
      // horizons are numbered below it (see discontinuity_mesh_engine.cpp).
      const bool event =
          std::all_of(surfaces.begin(), surfaces.end(), [](SurfaceId id) { return id >= 0; });
      if (!event || distance(segment.first, segment.second) < 1e-6) continue;
      const Vec3 p = (segment.first + segment.second) * 0.5;
      const auto query = engine.query(p, receiver.plane.normal);
      ++checked;
      // What the engine answers at the point is the reference's own value: counted, not compared.
      if (query && query->answer != DiscontinuityMeshEngine::Answer::kMesh) continue;
      ++byMesh;
      const double got = query ? query->irradiance.r : -1;  // -1: on no receiver
      const double expected = reference.irradiance(p, receiver.plane.normal, receiver.id).r;
      if (!(std::abs(got - expected) <= 1e-9 * std::max(1e-2, expected))) {
        if (failures++ == 0)
          ADD_FAILURE() << "on polygon " << receiver.id << " at (" << p.x << ", " << p.y << ", "
                        << p.z << "): dm " << got << ", reference " << expected;
      }
    }
  }
  std::printf("[ info     ] %d of %d edge midpoints answered by the mesh\n", byMesh, checked);
  EXPECT_GT(checked, 500);
  EXPECT_EQ(failures, 0) << failures << " of " << byMesh;
  // Measured (session 14): 3,040 of 3,052 (99.61%), since a point in a corner narrower than the
  // polylines' tolerance answers where the faces around it agree. Session 13: 3,023 (99.05%),
  // since the face near an EEE polyline is found by witness points beside the point (instead of
  // the faces' far samples), sides too close to call are computed exactly, and points in
  // rounding-thin slivers answer from the neighbour beside them; 2,857 (93.6%) before; 754
  // (24.7%) before the exact side test near EEE polylines. What is left: narrow corners whose
  // faces disagree at the point.
  EXPECT_GE(byMesh, 0.995 * checked);
}

// A point on the diagonal of a rotated box's triangulated face (an edge midpoint of its mesh,
// found by bench/dm_exactness): CGAL 5.5's landmark point location walked without end there
// (its _walk_from_face reads a flag it may leave unset); the trapezoidal map locates it. The
// query must return, on the reference's value (ctest's timeout stops a hang).
TEST(DiscontinuityMeshEngine, DegeneratePointOnATriangulatedBoxIsLocated) {
  const PosedScene scene = poseAt(loadScene(std::string(PENUMBRA_SOURCE_DIR) +
                                            "/tests/dm/data/rotated-boxes-triangulated.json"),
                                  0);
  DiscontinuityMeshEngine engine;
  engine.build(PosedScene(scene));
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  const Vec3 p{2.0127473515801384, 0.8604499387444815, 2.2850187280509573};
  const Vec3 n{-0.0087916587870639044, -0.82630426994392769, -0.56315536063168614};
  const auto query = engine.query(p, n);
  ASSERT_TRUE(query);
  const auto receiver = locateReceiver(scene, grid, p, n);
  ASSERT_TRUE(receiver);
  EXPECT_NEAR(query->irradiance.r, reference.irradiance(p, n, receiver->polygon).r, 1e-12);
}

// Faces that face verification leaves unresolved (a missing event crosses them; they are
// answered at the point), per bundled scene at frame 0: bounds at what is measured, so that a
// change that loses events shows; and no face left without labels. Measured (session 11) in
// brackets, session 9 after them: the difference is false alarms (labels that differ only by a
// degenerate vertex, same region) now told apart by evaluating the sample's labels at the corner
// (isAlias), and faces whose sample was degenerate now labelled at another point of them.
TEST(DiscontinuityMeshEngine, UnresolvedFacesInBundledScenes) {
  const std::vector<std::pair<const char*, long long>> bounds{
      {"/scenes/cornell-box/cornell-box.json", 0},  // [0] 1 and 3 unlabelled
      {"/scenes/office-desk/desk-145.json", 0},     // [0] 0
      {"/scenes/office-desk/desk-307.json", 0},     // [0] 3 and 1 unlabelled
      {"/scenes/office-desk/desk-475.json", 0},     // [1] 10 and 4 unlabelled
      {"/scenes/chair-room/chair-room.json", 0},    // [0] 0
  };
  // Session 14: one more in desk-307 and desk-475, found by probes that now reach corners beside
  // EEE polylines (farther in, along the corner's bisector): faces crossed by a missing event,
  // answered wrong before, now at the point. The chair room's (its floor near (2.39, 0, 2.306):
  // 1.4903 against 1.4960 over a strip 1 cm wide) was a stretch of an EEE surface seen between
  // a chair's back post and its seat, which the tracing's samples stepped over: it now brackets
  // the lines between separate blockers. Session 15: desk-307's and one of desk-475's were
  // coplanar edges crossed by a third (CoplanarEdgesCrossedByAnotherEdgeCompleteTheMesh); the
  // other of desk-475's, a turned stool's top edge and a panel's edge above it, parallel in the
  // model but 1e-16 out of one plane once rotated: their EEE quadric's valid lines, a rounding
  // wide, were found on one light edge and lost on the other. Within 1e-10 of the scene's size
  // such pairs are now coplanar (their plane's fans); a point of that face where the panel's edge
  // takes over (0.14% off with the top's labels) is answered by the mesh.
  for (const auto& [name, bound] : bounds) {
    DiscontinuityMeshEngine engine;
    engine.build(loadScene(std::string(PENUMBRA_SOURCE_DIR) + name), 0);
    if (std::string(name) == "/scenes/office-desk/desk-475.json") {
      const Vec3 p{0.937629663018, 0, 2.14410328189};
      const auto query = engine.query(p, {0, 1, 0});
      ASSERT_TRUE(query);
      EXPECT_EQ(query->answer, DiscontinuityMeshEngine::Answer::kMesh);
      const double expected = engine.irradianceAtPoint(0, p).r;
      EXPECT_NEAR(query->irradiance.r, expected, 1e-9 * expected);
    }
    std::printf("[ info     ] %s: %lld unresolved of %lld faces\n", name,
                engine.stats().unresolvedFaces, engine.stats().meshFaces);
    EXPECT_LE(engine.stats().unresolvedFaces, bound) << name;
    EXPECT_EQ(engine.stats().unlabelledBackprojections, 0) << name;
  }
}

// A card standing on the floor (one polygon, its foot on the receiver) with the whole light on one
// side: behind it a strip of umbra 1.75 mm wide runs along its foot. No event surface makes the
// foot's line (the EV fans through that edge meet the floor only at their hinge): it is a contact
// line. Without it the lit face on the light's side wraps around the foot into the strip: here
// face verification finds it unresolved (17 of these 30 points answered at the point), but in the
// dm_geometry fuzzer's scene (a wall 7.5e-8 high in a scene 6e-6 across) no corner check saw it
// and its labels (nothing hides the light) answered 0.32 where the reference gives 0.
TEST(DiscontinuityMeshEngine, CardStandingOnTheFloorBoundsItsUmbra) {
  test::SceneBuilder b = litRoom();
  b.addPolygon("white", {{1.7, 1.4, 0}, {2.3, 1.4, 0}, {2.3, 1.4, 0.05}, {1.7, 1.4, 0.05}});
  const PosedScene scene = b.pose();
  DiscontinuityMeshEngine engine;
  engine.build(PosedScene(scene));
  EXPECT_EQ(engine.stats().unresolvedFaces, 0);
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  const auto floor = std::find_if(scene.polygons.begin(), scene.polygons.end(),
                                  [](const WorldPolygon& q) { return q.bounds.max.z == 0; });
  ASSERT_NE(floor, scene.polygons.end());
  int byMesh = 0, points = 0;
  for (double x : {1.7001, 1.75, 2.0, 2.25, 2.2999})
    for (double behind : {1e-6, 1e-4, 5e-4, 1e-3, 1.7e-3, 1e-2}) {
      const Vec3 p{x, 1.4 - behind, 0}, up{0, 0, 1};
      const auto query = engine.query(p, up);
      ASSERT_TRUE(query);
      const double expected = reference.irradiance(p, up, floor->id).r;
      EXPECT_NEAR(query->irradiance.r, expected, 1e-9 * std::max(expected, 1e-2))
          << "at " << x << ", " << 1.4 - behind;
      ++points;
      byMesh += query->answer == DiscontinuityMeshEngine::Answer::kMesh ? 1 : 0;
    }
  EXPECT_EQ(byMesh, points);
}

// A panel lying flat on the floor (a rug: one polygon in the floor's plane, facing up) under a
// card tilted low over it. Each event line meets the floor and the panel at the same depth, and
// landed on whichever rounding put first: the other's faces there held no event. Where that was
// the floor, its faces' labels (the light whole) answered the floor's points under the panel,
// which the panel, passing through them, does not hide (DESIGN.md §5): the dm_geometry fuzzer
// found 0.319 where the reference gives 0.124, under a corner of an occluder 0.01 above a panel
// (fuzz/regressions/dm_geometry/mismatch-panel-lying-on-floor.bin). An event now lands on every
// polygon the line meets at the nearest depth, within the depth tolerance.
TEST(DiscontinuityMeshEngine, PanelLyingOnTheFloorHidesNothingUnderIt) {
  test::SceneBuilder b = litRoom();
  b.addPolygon("white", {{1.0, 1.0, 0}, {3.0, 1.0, 0}, {3.0, 3.0, 0}, {1.0, 3.0, 0}});
  b.addPolygon("white", {{1.6, 1.7, 0.02}, {2.4, 1.8, 0.12}, {2.2, 2.5, 0.05}});
  const PosedScene scene = b.pose();
  DiscontinuityMeshEngine engine;
  engine.build(PosedScene(scene));
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  // The floor and the panel: both receivers hold the points, and each mesh must answer them.
  std::vector<PolygonId> coincident;
  for (const WorldPolygon& q : scene.polygons)
    if (q.bounds.max.z == 0 && q.plane.normal.z > 0) coincident.push_back(q.id);
  ASSERT_EQ(coincident.size(), 2u);
  int compared = 0, shadowed = 0, points = 0;
  const Vec3 up{0, 0, 1};
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j) {
      const Vec3 p{1.5 + 1.1 * i / 40.0 + 1e-7, 1.5 + 1.1 * j / 40.0 + 2e-7, 0};
      ++points;
      const double unoccluded = 10 * reference.unoccludedFormFactor(p, up, scene.lights[0]);
      for (PolygonId receiver : coincident) {
        // The floor's and the panel's value at p are one: the same point, the same side.
        const double expected = reference.irradiance(p, up, receiver).r;
        if (receiver == coincident[0]) shadowed += expected < 0.999 * unoccluded ? 1 : 0;
        const auto face = engine.meshOf(receiver)->locate(p);
        ASSERT_TRUE(face) << "receiver " << receiver << " at " << p.x << ", " << p.y;
        if (engine.isAnsweredAtPoint(receiver, *face)) continue;
        EXPECT_NEAR(engine.faceIrradianceAt(receiver, *face, p).r, expected,
                    1e-9 * std::max(expected, 1e-2))
            << "receiver " << receiver << " at " << p.x << ", " << p.y;
        ++compared;
      }
      const auto query = engine.query(p, up);
      ASSERT_TRUE(query);
      EXPECT_NEAR(query->irradiance.r, reference.irradiance(p, up, coincident[0]).r,
                  1e-9 * std::max(query->irradiance.r, 1e-2));
    }
  // The card's shadow falls on the panel: 446 of the 1,681 points. Both meshes answer all of
  // them (before: here every tie went to the floor, and the panel's faces, holding no event,
  // were found crossed by missing events and answered none).
  EXPECT_GT(shadowed, points / 5);
  EXPECT_GT(compared, 2 * 0.99 * points);
}

// A card pushed through the floor: its side edges cross the receiver. The events of those edges
// start where they cross it (before that point the floor hides the lines, beyond it they meet
// the floor past the edge); visibility judged each stretch of a fan by its middle, and a stretch
// running from the edge's upper end to past the crossing was judged below the floor and lost
// whole (found by the dm_geometry fuzzer: 0.26% off under two tiny occluders crossing the floor).
TEST(DiscontinuityMeshEngine, CardThroughTheFloorIsExact) {
  test::SceneBuilder b = litRoom();
  b.addPolygon("white", {{1.7, 1.0, 0.3}, {2.3, 1.0, 0.3}, {2.3, 1.6, -0.9}, {1.7, 1.6, -0.9}});
  const PosedScene scene = b.pose();
  DiscontinuityMeshEngine engine;
  engine.build(PosedScene(scene));
  EXPECT_EQ(engine.stats().unresolvedFaces, 0);
  expectExact(scene, 1500, 7);
}

// A card standing on the light's edge (its corner on the edge, its plane across the light) hides
// a sliver of the light beside its corner from every floor point on one side of the edge's plane,
// and an L-shaped card between them hides part of that sliver. The visible region then has a
// vertex where the card's corner lies on the light edge, which no pair of features labels, so a
// backprojection there is unlabelled. The sample of the face holding these points sees none of
// the sliver, and face verification skipped the one corner whose probe did (unlabelled): its
// labels answered 0.0946 where the reference gives 0.0944 (0.24% high) over a band 0.25 m wide.
// Verification now asks an unlabelled probe whether the sample's labels give its light; and the
// fans through a crossing of the edge's plane (kLightEdgeParallelEdgeCrossing) are made for an
// occluder edge touching the light edge's line at one end, not only for one beside it.
TEST(DiscontinuityMeshEngine, CardStandingOnTheLightsEdgeIsExact) {
  test::SceneBuilder b = smallLampOverFloor();
  const Polygon3 l{{-0.5, 1, -0.5}, {0.3, 1, -0.5}, {0.3, 1, -0.1},
                   {-0.1, 1, -0.1}, {-0.1, 1, 0.5}, {-0.5, 1, 0.5}};
  b.addPolygon("white", l, "L");
  b.addPolygon("white", Polygon3(l.rbegin(), l.rend()), "L");
  b.addPolygon("white", {{0.25, 2, 0}, {0.25, 1.6, 0}, {0.6, 1.6, 0}, {0.6, 2, 0}}, "card");
  const PosedScene scene = b.pose();
  DiscontinuityMeshEngine engine;
  engine.build(PosedScene(scene));
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  const Vec3 up{0, 1, 0};
  int points = 0, wrong = 0;
  std::string first;
  for (double x : {0.2, 0.249999, 0.25, 0.250001, 0.26, 0.288047, 0.3, 0.35, 0.37, 0.4})
    for (double z = -1.3; z <= -0.95; z += 0.025) {
      const Vec3 p{x, 0, z};
      const auto query = engine.query(p, up);
      ASSERT_TRUE(query) << x << ", " << z;
      const double expected = reference.irradiance(p, up, 0).r;
      ++points;
      if (std::abs(query->irradiance.r - expected) > 1e-9 * std::max(expected, 1e-2) &&
          wrong++ == 0) {
        char text[160];
        std::snprintf(text, sizeof text, "at (%.9g, 0, %.9g): dm %.12g, reference %.12g", x, z,
                      query->irradiance.r, expected);
        first = text;
      }
    }
  EXPECT_EQ(wrong, 0) << wrong << " of " << points << " points, first " << first;
}

// A card crossing the light's plane beside the light, touching its edge: a point of the card on
// the light's plane, 3.75e-10 from the light's edge, lies within the locator's tolerance of the
// light polygon too, at distance 0 from its plane. The light was taken as the nearest receiver
// and, having no mesh, the query answered nothing (`probe` failed: "the point lies on no receiver
// facing its normal").
TEST(DiscontinuityMeshEngine, PointOfACardBesideTheLightIsAnswered) {
  test::SceneBuilder b = smallLampOverFloor();
  b.addPolygon("white",
               {{-0.625, 2.125, -0.125},
                {-0.25, 2.125, -0.125},
                {-0.25, 1.625, 0.375},
                {-0.625, 1.625, 0.375}},
               "card");
  const PosedScene scene = b.pose();
  DiscontinuityMeshEngine engine;
  engine.build(PosedScene(scene));
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  const Vec3 n = normalize(Vec3{0, -1, -1});
  for (const Vec3& p : {Vec3{-0.25000000037499998, 2, 0}, Vec3{-0.4, 2, 0}, Vec3{-0.3, 1.9, 0.1}}) {
    const auto query = engine.query(p, n);
    ASSERT_TRUE(query) << p;
    const double expected = reference.irradiance(p, n, 2).r;
    EXPECT_NEAR(query->irradiance.r, expected, 1e-9 * std::max(expected, 1e-2)) << p;
  }
}

TEST(DiscontinuityMeshEngine, FloatingBoxIsExact) {
  test::SceneBuilder b = litRoom();
  test::addBox(b, "white", "box", {1.6, 1.7, 1.2}, {2.3, 2.2, 1.6});
  expectExact(b.pose(), 1500, 1);
}

TEST(DiscontinuityMeshEngine, BoxRestingOnTheFloorIsExact) {
  test::SceneBuilder b = litRoom();
  test::addBox(b, "white", "box", {1.2, 1.4, 0}, {2.1, 2.0, 0.8});
  expectExact(b.pose(), 1500, 2);
}

TEST(DiscontinuityMeshEngine, TiltedTriangleIsExact) {
  test::SceneBuilder b = litRoom();
  b.addPolygon("white", {{1.3, 1.2, 1.0}, {2.6, 1.9, 1.5}, {1.9, 2.8, 1.2}});
  expectExact(b.pose(), 1500, 3);
}

TEST(DiscontinuityMeshEngine, RotatedBoxIsExact) {
  test::SceneBuilder b = litRoom();
  // A box turned about a tilted axis: no face parallel to the light or to the room.
  const Quaternion turn = Quaternion::fromAxisAngle(normalize(Vec3{1, 2, 0.5}), 0.7);
  for (Polygon3 face : test::boxFaces({-0.35, -0.25, -0.2}, {0.35, 0.25, 0.2})) {
    for (Vec3& v : face) v = turn.toMatrix() * v + Vec3{2.1, 1.9, 1.3};
    b.addPolygon("white", face, "box");
  }
  expectExact(b.pose(), 1500, 4);
}

TEST(DiscontinuityMeshEngine, TwoBoxesWithSeparateShadowsAreExact) {
  test::SceneBuilder b = litRoom();
  test::addBox(b, "white", "near", {0.4, 0.5, 0.9}, {0.9, 1.0, 1.3});
  test::addBox(b, "white", "far", {3.0, 2.9, 0.9}, {3.5, 3.4, 1.5});
  expectExact(b.pose(), 1500, 5);
}

// Degenerate configurations (issue: robustness).
TEST(DiscontinuityMeshEngine, CardWithCollinearVerticesIsExact) {
  test::SceneBuilder b = litRoom();
  b.addPolygon("white", {{1.6, 1.6, 1.2},
                         {2.0, 1.6, 1.2},
                         {2.4, 1.6, 1.2},
                         {2.4, 2.3, 1.2},
                         {2.0, 2.3, 1.2},
                         {1.6, 2.3, 1.2}});
  expectExact(b.pose(), 1500, 8);
}

TEST(DiscontinuityMeshEngine, CoplanarOccludersSharingAnEdgeAreExact) {
  test::SceneBuilder b = litRoom();
  b.addPolygon("white", {{1.4, 1.5, 1.3}, {2.0, 1.5, 1.3}, {2.0, 2.2, 1.3}, {1.4, 2.2, 1.3}},
               "card");
  b.addPolygon("white", {{2.0, 1.5, 1.3}, {2.6, 1.5, 1.3}, {2.6, 2.2, 1.3}, {2.0, 2.2, 1.3}},
               "card");
  expectExact(b.pose(), 1500, 9);
}

TEST(DiscontinuityMeshEngine, LightEdgeInThePlaneOfAnOccluderFaceIsExact) {
  test::SceneBuilder b = litRoom();
  // The box's face x = 1.5 contains the light's edge x = 1.5.
  test::addBox(b, "white", "box", {1.5, 1.8, 1.0}, {2.0, 2.3, 1.5});
  expectExact(b.pose(), 1500, 10);
}

// A triangulated copy of a scene: the diagonals join coplanar triangles and are never
// silhouettes, so the emitter events are the same and the result stays exact.
TEST(DiscontinuityMeshEngine, TriangulatedCopyGivesTheSameEventsAndStaysExact) {
  const auto build = [](bool triangulated) {
    test::SceneBuilder b = litRoom();
    const Quaternion turn = Quaternion::fromAxisAngle(normalize(Vec3{1, -1, 0.3}), 0.5);
    for (Polygon3 face : test::boxFaces({-0.35, -0.25, -0.2}, {0.35, 0.25, 0.2})) {
      for (Vec3& v : face) v = turn.toMatrix() * v + Vec3{2.1, 1.9, 1.3};
      if (!triangulated) {
        b.addPolygon("white", face, "box");
        continue;
      }
      b.addPolygon("white", {face[0], face[1], face[2]}, "box");
      b.addPolygon("white", {face[0], face[2], face[3]}, "box");
    }
    return b;
  };
  const PosedScene quads = build(false).pose(), triangles = build(true).pose();
  DiscontinuityMeshEngine a, b;
  a.build(PosedScene(quads));
  b.build(PosedScene(triangles));
  EXPECT_EQ(a.stats().surfacesEmitterVertex, b.stats().surfacesEmitterVertex);
  EXPECT_EQ(a.stats().surfacesEmitterEdge, b.stats().surfacesEmitterEdge);
  expectExact(triangles, 1500, 6);
  // The same points on both give the same irradiance.
  for (const ReceiverPoint& q : sampleReceiverPoints(quads, 300, 7)) {
    const auto x = a.irradiance(q.p, q.n), y = b.irradiance(q.p, q.n);
    ASSERT_TRUE(x && y);
    EXPECT_NEAR(x->r, y->r, 1e-9 * std::max(x->r, 1e-2));
  }
}

// The triangulated mesh: triangles tile every receiver, and every corner carries the exact
// irradiance (its face's backprojection evaluated there equals the reference at that point).
TEST(DiscontinuityMeshEngine, IrradianceMeshTilesReceiversWithExactCorners) {
  test::SceneBuilder b = litRoom();
  test::addBox(b, "white", "box", {1.6, 1.7, 1.2}, {2.3, 2.2, 1.6});
  const PosedScene scene = b.pose();
  DiscontinuityMeshEngine engine;
  engine.build(PosedScene(scene));
  const IrradianceMesh mesh = buildIrradianceMesh(engine, 0.5);
  std::map<PolygonId, double> area;
  double minimumArea = 0;
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    const Vec3& a = mesh.positions[mesh.indices[t]];
    const Vec3& c1 = mesh.positions[mesh.indices[t + 1]];
    const Vec3& c2 = mesh.positions[mesh.indices[t + 2]];
    const PolygonId receiver = mesh.receiverOf[mesh.indices[t]];
    // Counter-clockwise seen from the receiver's front.
    const double signedArea =
        0.5 * dot(cross(c1 - a, c2 - a), scene.polygons[receiver].plane.normal);
    // Slivers between events a rounding apart give triangles of area ~1e-20: none may be
    // inverted beyond that.
    EXPECT_GT(signedArea, -1e-15);
    minimumArea = std::min(minimumArea, signedArea);
    area[receiver] += signedArea;
  }
  for (const WorldPolygon& polygon : scene.polygons) {
    if (polygon.isLight) continue;
    EXPECT_NEAR(area[polygon.id], penumbra::area(polygon.vertices), 1e-9) << polygon.id;
  }
  const UniformGrid grid(scene);
  const ExactReference reference(scene, &grid);
  // Faces between events a rounding apart (slivers of area ~1e-20) hold labels of a degenerate
  // configuration; they cover no point a probe or a pixel can hit, so only corners of triangles
  // with some area are checked.
  int checked = 0;
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    const Vec3& a = mesh.positions[mesh.indices[t]];
    const double twiceArea = length(
        cross(mesh.positions[mesh.indices[t + 1]] - a, mesh.positions[mesh.indices[t + 2]] - a));
    if (twiceArea < 1e-12 || t % 5 != 0) continue;
    for (int k = 0; k < 3; ++k, ++checked) {
      const size_t i = mesh.indices[t + k];
      const PolygonId receiver = mesh.receiverOf[i];
      const Rgb expected =
          reference.irradiance(mesh.positions[i], scene.polygons[receiver].plane.normal, receiver);
      EXPECT_NEAR(mesh.irradiance[i].r, expected.r, 1e-9 * std::max(expected.r, 1e-2))
          << "corner " << k << " of triangle " << t / 3 << " (twice area " << twiceArea << ") at "
          << mesh.positions[i].x << " " << mesh.positions[i].y << " " << mesh.positions[i].z
          << " receiver " << receiver;
    }
  }
  EXPECT_GT(checked, 500);
  std::printf("smallest triangle area %g\n", minimumArea);
  EXPECT_FALSE(mesh.edges.empty());
}

}  // namespace
}  // namespace penumbra
