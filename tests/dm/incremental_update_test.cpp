// The discontinuity mesh's update against a full recomputation: after keyframe steps and after a
// caller's arbitrary rigid moves of an occluder and of the light, the updated solution's
// irradiance mesh (every corner's position and exact irradiance, every triangle, every
// discontinuity edge) equals, bit for bit, the one of an engine built from scratch at that pose;
// and the update did keep work (meshes and faces reused), so the equality is not that of two full
// computations.

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "penumbra/dm/irradiance_mesh.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {
namespace {

Scene load(const std::string& relative) {
  return loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + relative);
}

// The engine updated to `live`'s pose against one built from scratch at that pose.
void expectEqualsFull(const DiscontinuityMeshEngine& updated, const DynamicScene& live,
                      const std::string& where) {
  const DynamicScene scratch(live.scene(), live.posed().objectTransforms, live.extent(),
                             live.frame());
  DiscontinuityMeshEngine full;
  full.build(scratch);
  const auto difference = firstDifference(buildIrradianceMesh(updated), buildIrradianceMesh(full));
  EXPECT_FALSE(difference) << where << ": " << *difference;
  EXPECT_EQ(updated.stats().meshFaces, full.stats().meshFaces) << where;
  EXPECT_EQ(updated.stats().unresolvedFaces, full.stats().unresolvedFaces) << where;
  EXPECT_EQ(updated.stats().backprojectionVertices, full.stats().backprojectionVertices) << where;
}

TEST(DmUpdate, KeyframeStepsEqualFullRecomputation) {
  for (const char* name : {"office-desk/desk-145.json", "chair-room/chair-room.json"}) {
    const Scene scene = load(name);
    DynamicScene live(scene, 0);
    DiscontinuityMeshEngine engine;
    engine.build(live);
    for (int frame = 1; frame < scene.frames; ++frame) {
      const SceneChange change = live.changeToFrame(frame);
      live.apply(change);
      engine.update(live, change);
      const DmStats& s = engine.stats();
      EXPECT_FALSE(s.recomputedAll);
      EXPECT_GT(s.keptMeshes, 0) << name << " frame " << frame;
      // Most kept meshes are far from the mover: their inputs are carried over, not assembled.
      EXPECT_GT(s.carriedInputs, s.keptMeshes / 2) << name << " frame " << frame;
      EXPECT_LE(s.carriedInputs, s.keptMeshes) << name << " frame " << frame;
      // Planes of parallel edges whose fans all kept their cuts take their surfaces over whole.
      EXPECT_GT(s.keptParallelPlanes, 0) << name << " frame " << frame;
      EXPECT_GT(s.examinedParallelPlanes, 0) << name << " frame " << frame;
      EXPECT_GT(s.reusedFaces, s.meshFaces / 10) << name << " frame " << frame;
      EXPECT_EQ(s.reusedFaces + s.recomputedFaces, s.meshFaces);
      expectEqualsFull(engine, live, std::string(name) + " frame " + std::to_string(frame));
    }
  }
}

TEST(DmUpdate, ArbitraryMovesOfAnOccluderAndOfTheLightEqualFullRecomputation) {
  const Scene scene = load("cornell-box/cornell-box.json");
  DynamicScene live(scene, 0);
  DiscontinuityMeshEngine engine;
  engine.build(live);
  int light = -1, block = -1;
  for (int o = 0; o < int(scene.objects.size()); ++o) {
    for (int m : scene.objects[o].polygonMaterial)
      if (scene.materials[m].isEmitter()) light = o;
    if (scene.objects[o].isDynamic()) block = o;
  }
  ASSERT_GE(light, 0);
  ASSERT_GE(block, 0);
  const auto turnAbout = [&](int object, double radians, const Vec3& shift) {
    const PosedScene& posed = live.posed();
    Box3 box;
    for (PolygonId id = posed.objectFirstPolygon[object]; id < posed.objectFirstPolygon[object + 1];
         ++id)
      box.extend(posed.polygons[id].bounds);
    const Vec3 c = box.center();
    const Quaternion q = Quaternion::fromAxisAngle({0, 1, 0}, radians);
    return Transform::fromTrs(c + shift - q.toMatrix() * c, q, {1, 1, 1}) *
           live.transformOf(object);
  };
  const auto step = [&](const SceneChange& change, const std::string& what) {
    live.apply(change);
    engine.update(live, change);
    expectEqualsFull(engine, live, what);
  };
  step(live.changeMoving(block, turnAbout(block, 0.4, {0.03, 0, -0.02})), "block turned");
  step(live.changeMoving(block, turnAbout(block, -0.1, {0, 0.05, 0})), "block lifted");
  EXPECT_GT(engine.stats().carriedInputs, 0);
  step(live.changeMoving(light, turnAbout(light, 0.2, {0.05, -0.01, 0})), "light moved");
  // A moved light changes every receiver's light-plane and horizon events: nothing carried.
  EXPECT_EQ(engine.stats().carriedInputs, 0);
  step(live.changeToFrame(2), "back on the keyframes at frame 2");
}

// Two full computations of the same pose in one process are identical (rounding a mesh vertex
// once read the lazy exact number's current interval, which earlier exact predicates had
// tightened, so the second build of the chair room differed from the first by ulps).
TEST(DmUpdate, FullComputationDoesNotDependOnWhatRanBefore) {
  const Scene scene = load("chair-room/chair-room.json");
  std::optional<IrradianceMesh> first;
  for (int k = 0; k < 2; ++k) {
    const DynamicScene live(scene, 1);
    DiscontinuityMeshEngine engine;
    engine.build(live);
    const IrradianceMesh mesh = buildIrradianceMesh(engine);
    if (!first) {
      first = mesh;
      continue;
    }
    const auto difference = firstDifference(*first, mesh);
    EXPECT_FALSE(difference) << *difference;
  }
}

}  // namespace
}  // namespace penumbra
