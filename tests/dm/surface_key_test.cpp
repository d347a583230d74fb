// Stable surface keys (dm/surface_key.h): the references name what they say, keys are unique in a
// frame, and after updates — keyframe steps, an occluder turned and lifted off the floor and set
// back on it, the light moved — the surface under each key is, bit for bit, the one a full build
// at that pose makes under it, though the two lists need not hold the surfaces in one order.

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>

#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/dm/surface_key.h"
#include "penumbra/geometry/transform.h"
#include "penumbra/scene/scene_loader.h"
#include "support/rigid_moves.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

Scene load(const std::string& relative) {
  return loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + relative);
}

TEST(SurfaceKeys, ReferencesNameTheirVertexAndEdge) {
  const Scene scene = load("office-desk/desk-145.json");
  const DynamicScene live(scene, 0);
  const EdgeAdjacency adjacency(live.posed());
  for (VertexId v = 0; v < VertexId(adjacency.vertices().size()); ++v) {
    const FeatureRef ref = vertexRef(adjacency, v);
    const std::vector<PolygonId>& polygons = adjacency.vertices()[size_t(v)].polygons;
    EXPECT_EQ(ref.polygon, *std::min_element(polygons.begin(), polygons.end()));
    EXPECT_EQ(adjacency.polygonVertices(ref.polygon)[size_t(ref.corner)], v);
  }
  for (EdgeId e = 0; e < EdgeId(adjacency.edges().size()); ++e) {
    const FeatureRef ref = edgeRef(adjacency, e);
    const std::vector<VertexId>& corners = adjacency.polygonVertices(ref.polygon);
    EXPECT_EQ(adjacency.edgeBetween(corners[size_t(ref.corner)],
                                    corners[(size_t(ref.corner) + 1) % corners.size()]),
              e);
  }
}

bool sameSurface(const DiscontinuitySurface& a, const DiscontinuitySurface& b) {
  const auto sameCuts = [](const SurfaceIntersection& p, const SurfaceIntersection& q) {
    return p.polygon == q.polygon && p.p0 == q.p0 && p.p1 == q.p1 &&
           p.boundaryAt0 == q.boundaryAt0 && p.boundaryAt1 == q.boundaryAt1;
  };
  return a.kind == b.kind && a.light == b.light && a.lightFeature == b.lightFeature &&
         a.hingePolygons == b.hingePolygons && a.fan.source0 == b.fan.source0 &&
         a.fan.source1 == b.fan.source1 && a.fan.hinge0 == b.fan.hinge0 &&
         a.fan.hinge1 == b.fan.hinge1 && a.fan.contacts == b.fan.contacts && a.cells == b.cells &&
         std::equal(a.intersections.begin(), a.intersections.end(), b.intersections.begin(),
                    b.intersections.end(), sameCuts);
}

// The surfaces by key; fails on a key given twice.
std::map<SurfaceKey, size_t> byKey(const DiscontinuityMeshEngine& engine, const std::string& what) {
  const std::vector<SurfaceKey> keys = surfaceKeys(engine.surfaces(), engine.adjacency());
  std::map<SurfaceKey, size_t> map;
  for (size_t i = 0; i < keys.size(); ++i)
    EXPECT_TRUE(map.emplace(keys[i], i).second) << what << ": surface " << i << "'s key twice";
  return map;
}

// The updated engine's surfaces against those of a full build at `live`'s pose, by key. Counts
// the surfaces whose position in the two lists differs.
void expectSameSurfacesByKey(const DiscontinuityMeshEngine& updated, const DynamicScene& live,
                             const std::string& what, long long& moved) {
  const DynamicScene scratch(live.scene(), live.posed().objectTransforms, live.extent(),
                             live.frame());
  DiscontinuityMeshEngine full;
  full.build(scratch);
  const std::map<SurfaceKey, size_t> now = byKey(updated, what + " (update)");
  const std::map<SurfaceKey, size_t> fresh = byKey(full, what + " (full)");
  ASSERT_EQ(now.size(), fresh.size()) << what;
  ASSERT_EQ(now.size(), updated.surfaces().size()) << what;
  int differing = 0;
  for (auto a = now.begin(), b = fresh.begin(); a != now.end(); ++a, ++b) {
    ASSERT_TRUE(a->first == b->first) << what << ": the key sets differ";
    if (!sameSurface(updated.surfaces()[a->second], full.surfaces()[b->second])) ++differing;
    moved += a->second != b->second ? 1 : 0;
  }
  EXPECT_EQ(differing, 0) << what;
}

TEST(SurfaceKeys, NameTheSameSurfaceAfterAnUpdateAsInAFullBuild) {
  long long moved = 0;
  for (const char* name : {"office-desk/desk-145.json", "chair-room/chair-room.json"}) {
    const Scene scene = load(name);
    DynamicScene live(scene, 0);
    DiscontinuityMeshEngine engine;
    engine.build(live);
    byKey(engine, name);
    for (int frame = 1; frame < scene.frames; ++frame) {
      const SceneChange change = live.changeToFrame(frame);
      live.apply(change);
      engine.update(live, change);
      expectSameSurfacesByKey(engine, live, std::string(name) + " frame " + std::to_string(frame),
                              moved);
    }
  }
  // Rigid moves off the keyframes: a block turned, lifted off the floor (its bottom's vertices no
  // longer the floor's: their references change) and set down again, and the light moved.
  const Scene scene = load("cornell-box/cornell-box.json");
  DynamicScene live(scene, 0);
  DiscontinuityMeshEngine engine;
  engine.build(live);
  const auto [light, block] = test::lightAndMovingObject(scene);
  ASSERT_GE(light, 0);
  ASSERT_GE(block, 0);
  const auto step = [&](const SceneChange& change, const std::string& what) {
    live.apply(change);
    engine.update(live, change);
    expectSameSurfacesByKey(engine, live, what, moved);
  };
  step(live.changeMoving(block, test::turnedAbout(live, block, 0.4, {0.03, 0, -0.02})),
       "block turned");
  step(live.changeMoving(block, test::turnedAbout(live, block, -0.1, {0, 0.05, 0})),
       "block lifted");
  step(live.changeMoving(block, test::turnedAbout(live, block, 0.2, {0, -0.05, 0})),
       "block set down");
  step(live.changeMoving(light, test::turnedAbout(live, light, 0.2, {0.05, -0.01, 0})),
       "light moved");
  step(live.changeToFrame(2), "back on the keyframes at frame 2");
  // Today an update's list holds the surfaces in the order of a full build's (the keys agree
  // by position too); the keys are for lists that will not.
  EXPECT_EQ(moved, 0);
}

// A moving box listed before a static one comes to touch it corner to corner: the scene's
// vertices are numbered in the order the polygons list them, one point once, so the weld
// renumbers every vertex and edge after the shared corner. A surface the move leaves as it was
// (the same generators, the same fan) keeps its key all the same.
constexpr const char* kCornerWeld = R"({"penumbra": 1, "materials": {
  "white": {"reflectance": [0.7, 0.7, 0.7]},
  "lamp": {"reflectance": [0, 0, 0], "emission": [10, 10, 10]}},
 "objects": [
  {"name": "floor", "material": "white", "polygons": [[[-2,0,2],[2,0,2],[2,0,-2],[-2,0,-2]]]},
  {"name": "mover", "material": "white", "polygons": [
   [[0,0.25,0],[0,0.25,0.25],[0.25,0.25,0.25],[0.25,0.25,0]],
   [[0,0,0],[0.25,0,0],[0.25,0,0.25],[0,0,0.25]],
   [[0,0,0.25],[0.25,0,0.25],[0.25,0.25,0.25],[0,0.25,0.25]],
   [[0,0,0],[0,0.25,0],[0.25,0.25,0],[0.25,0,0]],
   [[0.25,0,0],[0.25,0.25,0],[0.25,0.25,0.25],[0.25,0,0.25]],
   [[0,0,0],[0,0,0.25],[0,0.25,0.25],[0,0.25,0]]],
   "motion": [{"frame": 0, "translate": [-1,0,-1]}, {"frame": 1, "translate": [-0.25,0,-0.25]}]},
  {"name": "block", "material": "white", "polygons": [
   [[0,0.75,0],[0,0.75,0.5],[0.5,0.75,0.5],[0.5,0.75,0]],
   [[0,0.25,0],[0.5,0.25,0],[0.5,0.25,0.5],[0,0.25,0.5]],
   [[0,0.25,0.5],[0.5,0.25,0.5],[0.5,0.75,0.5],[0,0.75,0.5]],
   [[0,0.25,0],[0,0.75,0],[0.5,0.75,0],[0.5,0.25,0]],
   [[0.5,0.25,0],[0.5,0.75,0],[0.5,0.75,0.5],[0.5,0.25,0.5]],
   [[0,0.25,0],[0,0.25,0.5],[0,0.75,0.5],[0,0.75,0]]]},
  {"name": "lamp", "material": "lamp",
   "polygons": [[[-0.2,2,-0.2],[0.2,2,-0.2],[0.2,2,0.2],[-0.2,2,0.2]]]}]})";

bool sameGenerators(const DiscontinuitySurface& a, const DiscontinuitySurface& b) {
  return a.kind == b.kind && a.light == b.light && a.lightFeature == b.lightFeature &&
         a.hingePolygons == b.hingePolygons && a.fan.source0 == b.fan.source0 &&
         a.fan.source1 == b.fan.source1 && a.fan.hinge0 == b.fan.hinge0 &&
         a.fan.hinge1 == b.fan.hinge1 && a.fan.contacts == b.fan.contacts;
}

TEST(SurfaceKeys, AreKeptByASurfaceTheMoveLeavesAloneThoughTheAdjacencyIsRenumbered) {
  const test::TempDir dir;
  const Scene scene = loadScene(dir.write("corner-weld.json", kCornerWeld));
  DynamicScene live(scene, 0);
  DiscontinuityMeshEngine engine;
  engine.build(live);
  const std::vector<DiscontinuitySurface> before = engine.surfaces();
  const std::vector<SurfaceKey> keysBefore = surfaceKeys(before, engine.adjacency());
  const size_t verticesBefore = engine.adjacency().vertices().size();
  const SceneChange change = live.changeToFrame(1);
  live.apply(change);
  engine.update(live, change);
  ASSERT_EQ(engine.adjacency().vertices().size() + 1, verticesBefore) << "the corners did not weld";
  const std::vector<SurfaceKey> keysNow = surfaceKeys(engine.surfaces(), engine.adjacency());
  int kept = 0, renumbered = 0;
  for (size_t i = 0; i < engine.surfaces().size(); ++i) {
    const DiscontinuitySurface& s = engine.surfaces()[i];
    const auto same = [&](const DiscontinuitySurface& b) { return sameGenerators(s, b); };
    const auto match = std::find_if(before.begin(), before.end(), same);
    if (match == before.end()) continue;
    ASSERT_EQ(std::count_if(before.begin(), before.end(), same), 1);
    const size_t j = size_t(match - before.begin());
    EXPECT_TRUE(keysNow[i] == keysBefore[j]) << "surface " << i << " (frame before: " << j << ")";
    ++kept;
    renumbered +=
        s.occluderFeature != match->occluderFeature || s.secondFeature != match->secondFeature;
  }
  // Most of the static block's and the floor's surfaces (100 of 176 and 220); the block's vertices
  // and edges after the shared corner have other ids in the adjacency now (14 of the surfaces).
  EXPECT_GT(kept, 0);
  EXPECT_GT(renumbered, 0);
}

}  // namespace
}  // namespace penumbra
