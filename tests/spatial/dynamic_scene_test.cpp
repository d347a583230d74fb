// The live scene's change model and the structures that move with it: after arbitrary rigid moves
// of any object (not keyframes, and out of the keyframes' bounds), the grid's cell lists and the
// ray caster's hits equal those of structures built from scratch at that pose, and the grid's
// lists equal a brute-force clipping of every polygon against every cell.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "penumbra/scene/reach_bounds.h"
#include "penumbra/scene/scene_loader.h"
#include "penumbra/spatial/dynamic_scene.h"

namespace penumbra {
namespace {

Scene loadBundled(const std::string& name) {
  return loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + name);
}

int lightObject(const Scene& scene) {
  for (int o = 0; o < int(scene.objects.size()); ++o)
    for (int m : scene.objects[o].polygonMaterial)
      if (scene.materials[m].isEmitter()) return o;
  return -1;
}

Transform randomRigid(std::mt19937_64& random, const Box3& around, double reach) {
  std::uniform_real_distribution<double> unit(-1, 1);
  const Vec3 axis = normalize(Vec3{unit(random), unit(random), unit(random)} + Vec3{0, 1e-3, 0});
  const Quaternion rotation = Quaternion::fromAxisAngle(axis, 3.2 * unit(random));
  const Vec3 translate = around.center() + Vec3{unit(random), unit(random), unit(random)} * reach;
  return Transform::fromTrs(translate, rotation, {1, 1, 1});
}

// Same cells (resolution, bounds) and the same sorted polygon list in every cell, bit for bit.
void expectSameGrid(const UniformGrid& a, const UniformGrid& b) {
  ASSERT_EQ(a.resolution().nx, b.resolution().nx);
  ASSERT_EQ(a.resolution().ny, b.resolution().ny);
  ASSERT_EQ(a.resolution().nz, b.resolution().nz);
  ASSERT_EQ(a.bounds().min, b.bounds().min);
  ASSERT_EQ(a.bounds().max, b.bounds().max);
  for (int cell = 0; cell < a.resolution().cellCount(); ++cell)
    ASSERT_EQ(a.polygonsInCell(cell), b.polygonsInCell(cell)) << "cell " << cell;
}

// Independent of the grid's incremental code: every polygon clipped against every cell.
void expectBruteForceGrid(const UniformGrid& grid, const PosedScene& posed) {
  for (int cell = 0; cell < grid.resolution().cellCount(); ++cell) {
    std::vector<PolygonId> expected;
    for (const WorldPolygon& p : posed.polygons)
      if (p.bounds.overlaps(grid.cellBounds(cell)) &&
          polygonCutsBox(p.vertices, grid.cellBounds(cell)))
        expected.push_back(p.id);
    ASSERT_EQ(grid.polygonsInCell(cell), expected) << "cell " << cell;
  }
}

// The same closest hit (polygon and parameter, bit for bit) and the same occlusion answers for
// rays and segments through the scene, many of them aimed at the moved object.
void expectSameHits(const RayCaster& a, const RayCaster& b, const PosedScene& posed, int object,
                    const Box3& region, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  const Box3 extent = region;
  const auto inside = [&] {
    const Vec3 d = extent.diagonal();
    return extent.min + Vec3{unit(random) * d.x, unit(random) * d.y, unit(random) * d.z};
  };
  Box3 target;
  for (PolygonId id = posed.objectFirstPolygon[object]; id < posed.objectFirstPolygon[object + 1];
       ++id)
    target.extend(posed.polygons[id].bounds);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 origin = inside();
    Vec3 aim = inside();
    if (i % 2 == 0 && !target.isEmpty()) {
      const Vec3 d = target.diagonal();
      aim = target.min + Vec3{unit(random) * d.x, unit(random) * d.y, unit(random) * d.z};
    }
    if (aim == origin) continue;
    const auto ha = a.intersect(origin, aim - origin, 0, INFINITY);
    const auto hb = b.intersect(origin, aim - origin, 0, INFINITY);
    ASSERT_EQ(ha.has_value(), hb.has_value()) << "ray " << i;
    if (ha) {
      ++hits;
      EXPECT_EQ(ha->polygon, hb->polygon) << "ray " << i;
      EXPECT_EQ(ha->t, hb->t) << "ray " << i;
    }
    EXPECT_EQ(a.isOccluded(origin, aim), b.isOccluded(origin, aim)) << "segment " << i;
  }
  EXPECT_GT(hits, 1000);
}

TEST(DynamicScene, ArbitraryMovesKeepGridAndRayCasterEqualToAFreshBuild) {
  const Scene scene = loadBundled("office-desk/desk-145.json");
  DynamicScene live(scene, 0);
  std::mt19937_64 random(11);
  const Box3 room = live.extent();
  // The keyframed box, a static object and the light.
  std::vector<int> movers;
  for (int o = 0; o < int(scene.objects.size()); ++o)
    if (scene.objects[o].isDynamic()) movers.push_back(o);
  for (int o = int(scene.objects.size()) - 1; o >= 0; --o)
    if (!scene.objects[o].isDynamic() && o != lightObject(scene)) {
      movers.push_back(o);
      break;
    }
  movers.push_back(lightObject(scene));
  ASSERT_EQ(movers.size(), 3u);
  for (int step = 0; step < 12; ++step) {
    const int object = movers[step % movers.size()];
    // Mostly inside the room; every fourth step far outside it (the extent must grow).
    const double reach = step % 4 == 3 ? 3 * room.diagonalLength() : 0.3 * room.diagonalLength();
    const SceneChange change = live.changeMoving(object, randomRigid(random, room, reach));
    ASSERT_EQ(change.moves.size(), 1u);
    EXPECT_EQ(change.moves[0].object, object);
    EXPECT_TRUE(change.moves[0].swept.overlaps(change.moves[0].boundsAfter));
    const long long before = live.modificationCount(object);
    live.apply(change);
    EXPECT_EQ(live.modificationCount(object), before + 1);

    const DynamicScene fresh(scene, live.posed().objectTransforms, live.extent(), live.frame());
    expectSameGrid(live.grid(), fresh.grid());
    expectSameHits(live.rays(), fresh.rays(), live.posed(), object, room, 100 + step);
    EXPECT_EQ(live.rays().epsilon(), fresh.rays().epsilon());
    for (size_t i = 0; i < live.posed().polygons.size(); ++i)
      ASSERT_EQ(live.posed().polygons[i].vertices, fresh.posed().polygons[i].vertices);
  }
  expectBruteForceGrid(live.grid(), live.posed());
}

TEST(DynamicScene, KeyframeStepsNameExactlyTheMovedObjects) {
  const Scene scene = loadBundled("office-desk/desk-145.json");
  DynamicScene live(scene, 0);
  const Box3 extent = live.extent();
  for (int frame = 1; frame < scene.frames; ++frame) {
    const SceneChange change = live.changeToFrame(frame);
    EXPECT_EQ(change.frameBefore, frame - 1);
    EXPECT_EQ(change.frameAfter, frame);
    EXPECT_FALSE(change.extentGrows);  // the keyframes' reach covers every keyframe pose
    ASSERT_EQ(change.moves.size(), 1u);
    EXPECT_TRUE(scene.objects[change.moves[0].object].isDynamic());
    EXPECT_FALSE(change.movesLight());
    live.apply(change);
    EXPECT_EQ(live.extent().min, extent.min);  // tolerances never change along the keyframes
    EXPECT_EQ(live.extent().max, extent.max);
    const DynamicScene fresh(scene, frame);
    expectSameGrid(live.grid(), fresh.grid());
  }
  // Staying put is an empty change.
  EXPECT_TRUE(live.changeToFrame(live.frame()).moves.empty());
  expectBruteForceGrid(live.grid(), live.posed());
}

TEST(DynamicScene, MovingALightSaysSo) {
  const Scene scene = loadBundled("cornell-box/cornell-box.json");
  DynamicScene live(scene, 0);
  const int light = lightObject(scene);
  ASSERT_GE(light, 0);
  const Transform down{Mat3{}, Vec3{0, -0.05, 0}};
  const SceneChange change = live.changeMoving(light, down * live.transformOf(light));
  EXPECT_TRUE(change.movesLight());
  live.apply(change);
  const DynamicScene fresh(scene, live.posed().objectTransforms, live.extent(), live.frame());
  expectSameGrid(live.grid(), fresh.grid());
}

// The swept bounds of a keyframe step contain the object at every sub-frame of the step, rotations
// included (checked against the motion's own interpolation, sampled finely), and stay close to
// the object for an object modelled far from its origin.
TEST(ReachBounds, SweptBoundsContainEveryInterpolatedPose) {
  SceneObject object;
  object.polygons = {{{1, 0, 0}, {2, 0, 0}, {2, 1, 0.5}, {1, 1, 0.5}},
                     {{0, 0, 3}, {0, 1, 3}, {0.5, 0, 3}}};
  const Quaternion small = Quaternion::fromAxisAngle({0, 0, 1}, 0.01);  // slerp's nlerp branch
  object.motion = Motion(
      {{0, {Vec3{0, 0, 0}, Quaternion{}, {1, 1, 1}}},
       {1, {Vec3{3, 1, -2}, Quaternion::fromAxisAngle(normalize(Vec3{1, 2, 3}), 2.5), {2, 0.5, 1}}},
       {4, {Vec3{-1, 0, 0}, Quaternion::fromAxisAngle({0, 1, 0}, -1), {1, 1, 1}}},
       {5, {Vec3{-1, 0, 0}, small, {1, 1, 1}}}});
  const Box3 reach = reachBounds(object);
  const auto& keys = object.motion.keyframes();
  for (size_t k = 1; k < keys.size(); ++k) {
    const Box3 swept = sweptBounds(object, keys[k - 1].frame, keys[k].frame);
    for (int i = 0; i <= 400; ++i) {
      const double frame = keys[k - 1].frame + (keys[k].frame - keys[k - 1].frame) * i / 400.0;
      const Box3 at = transformedBounds(object.polygons, object.transformAt(frame));
      const Box3 slack = swept.expanded(1e-12);
      EXPECT_TRUE(slack.contains(at.min) && slack.contains(at.max)) << "frame " << frame;
      EXPECT_TRUE(reach.expanded(1e-12).contains(at.min) && reach.expanded(1e-12).contains(at.max));
    }
  }
  // A unit square modelled 100 units from its origin, turned by 29 degrees and moved back (the
  // keyframes put it in place at both ends; in between the linear translation lets it swing
  // about a unit): the sweep stays within a few object sizes of the true sweep, not the 100-unit
  // lever arm.
  SceneObject far;
  far.polygons = {{{100, 0, 0}, {101, 0, 0}, {101, 1, 0}, {100, 1, 0}}};
  const Quaternion turn = Quaternion::fromAxisAngle({0, 0, 1}, 0.5);
  const Vec3 pivot{100.5, 0.5, 0};
  far.motion = Motion({{0, {Vec3{}, Quaternion{}, {1, 1, 1}}},
                       {1, {pivot - turn.toMatrix() * pivot, turn, {1, 1, 1}}}});
  Box3 sampled;
  for (int i = 0; i <= 1000; ++i)
    sampled.extend(transformedBounds(far.polygons, far.transformAt(i / 1000.0)));
  const Box3 swept = sweptBounds(far, 0, 1);
  EXPECT_TRUE(swept.contains(sampled.min) && swept.contains(sampled.max));
  EXPECT_LT(swept.diagonalLength(), sampled.diagonalLength() + 4.0);
}

}  // namespace
}  // namespace penumbra
