// Backprojections propagated from face to neighbouring face (DmOptions::propagateBackprojections)
// against those computed from scratch at every face: the same labels, the same labelled-ness and
// the same unresolved faces, on bundled scenes, a generated one, and one whose mesh lacks events
// (EEE surfaces off), where verification must send the faces it cannot vouch for back to scratch.

#include <gtest/gtest.h>

#include <string>

#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/scene/scene_generator.h"
#include "penumbra/scene/scene_loader.h"
#include "support/boxes.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

void expectSameAsFromScratch(const PosedScene& scene, DmOptions options = {}) {
  options.propagateBackprojections = false;
  DiscontinuityMeshEngine scratch(options);
  options.propagateBackprojections = true;
  DiscontinuityMeshEngine propagated(options);
  scratch.build(PosedScene(scene));
  propagated.build(PosedScene(scene));
  EXPECT_EQ(scratch.stats().propagatedBackprojections, 0);
  EXPECT_GT(propagated.stats().propagatedBackprojections, 0);
  EXPECT_EQ(propagated.stats().meshFaces, scratch.stats().meshFaces);
  EXPECT_EQ(propagated.stats().unresolvedFaces, scratch.stats().unresolvedFaces);
  EXPECT_EQ(propagated.stats().unlabelledBackprojections,
            scratch.stats().unlabelledBackprojections);
  int differing = 0;
  for (const WorldPolygon& polygon : scene.polygons) {
    const ReceiverMesh* mesh = scratch.meshOf(polygon.id);
    if (!mesh) continue;
    for (const MeshFace& face : mesh->faces()) {
      EXPECT_EQ(propagated.isUnresolved(polygon.id, face.index),
                scratch.isUnresolved(polygon.id, face.index));
      const auto& a = scratch.faceBackprojections(polygon.id, face.index);
      const auto& b = propagated.faceBackprojections(polygon.id, face.index);
      ASSERT_EQ(a.size(), b.size());
      for (size_t l = 0; l < a.size(); ++l) {
        const bool same = a[l].isLabelled == b[l].isLabelled &&
                          (!a[l].isLabelled || sameLabels(a[l], b[l], scratch.adjacency()));
        if (!same && differing++ == 0)
          ADD_FAILURE() << "labels differ on polygon " << polygon.id << ", face " << face.index
                        << ", light " << l;
      }
    }
  }
  EXPECT_EQ(differing, 0);
}

PosedScene bundled(const std::string& path) {
  return poseAt(loadScene(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + path), 0);
}

TEST(BackprojectionPropagation, CornellBoxMatchesFromScratch) {
  expectSameAsFromScratch(bundled("cornell-box/cornell-box.json"));
}

TEST(BackprojectionPropagation, Desk145MatchesFromScratch) {
  expectSameAsFromScratch(bundled("office-desk/desk-145.json"));
}

TEST(BackprojectionPropagation, ChairRoomMatchesFromScratch) {
  expectSameAsFromScratch(bundled("chair-room/chair-room.json"));
}

TEST(BackprojectionPropagation, GeneratedSceneMatchesFromScratch) {
  const test::TempDir dir;
  const std::string path = dir.write("generated.json", generateSceneJson({300, 7, 1}));
  expectSameAsFromScratch(poseAt(loadScene(path), 0));
}

// Two boxes turned about tilted axes, one above the other: without EEE surfaces the faces where
// their shadows overlap are crossed by events the mesh lacks.
TEST(BackprojectionPropagation, MissingEventsMatchFromScratch) {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5}).addMaterial("lamp", {0, 0, 0}, {10, 10, 10});
  test::addRoom(b, "white", {0, 0, 0}, {4, 4, 3});
  b.addPolygon("lamp", {{1.5, 1.5, 2.9}, {1.5, 2.5, 2.9}, {2.5, 2.5, 2.9}, {2.5, 1.5, 2.9}});
  test::addTiltedBoxPair(b, "white");
  expectSameAsFromScratch(b.pose(), {.eeeSurfaces = false});
  expectSameAsFromScratch(b.pose());
}

}  // namespace
}  // namespace penumbra
