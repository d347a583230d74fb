#include "penumbra/scene/scene_generator.h"

#include <gtest/gtest.h>

#include "scene_json_checks.h"

namespace penumbra {
namespace {

using namespace scene_checks;

std::string join(const std::vector<std::string>& problems) {
  std::string text;
  for (const std::string& p : problems) text += "\n  " + p;
  return text;
}

// Everything a generated scene promises, except the count.
void expectValid(const JsonScene& scene) {
  EXPECT_TRUE(findPolygonProblems(scene).empty()) << join(findPolygonProblems(scene));
  EXPECT_TRUE(findRoomProblems(scene).empty()) << join(findRoomProblems(scene));
  EXPECT_TRUE(findSolidProblems(scene).empty()) << join(findSolidProblems(scene));
  EXPECT_TRUE(findLightProblems(scene).empty()) << join(findLightProblems(scene));
  EXPECT_TRUE(findOverlapProblems(scene, /*objectBoxes=*/true).empty())
      << join(findOverlapProblems(scene, true));
  EXPECT_TRUE(findCameraProblems(scene).empty()) << join(findCameraProblems(scene));
}

const JsonObject* findObject(const JsonScene& scene, const std::string& name) {
  for (const JsonObject& o : scene.objects)
    if (o.name == name) return &o;
  return nullptr;
}

class GeneratedSceneTest : public ::testing::TestWithParam<int> {};

TEST_P(GeneratedSceneTest, HasTheTargetCountAndIsValid) {
  const int target = GetParam();
  const JsonScene scene =
      parseSceneText(generateSceneJson({.targetPolygons = target, .seed = 7, .frames = 4}));
  EXPECT_EQ(scene.polygonCount(), target);  // the generator promises exact counts from 54 up
  EXPECT_EQ(scene.frames, 4);
  int lights = 0;
  for (const JsonObject& o : scene.objects) lights += o.emitter ? int(o.polygons.size()) : 0;
  EXPECT_EQ(lights, 1);
  const JsonObject* box = findObject(scene, "floating-box");
  ASSERT_NE(box, nullptr);
  EXPECT_TRUE(box->isDynamic());
  EXPECT_EQ(box->motion.keyframes().size(), 4u);
  EXPECT_EQ(box->polygons.size(), 6u);
  expectValid(scene);
}

INSTANTIATE_TEST_SUITE_P(Targets, GeneratedSceneTest, ::testing::Values(100, 1000, 10000));

TEST(SceneGenerator, IsDeterministicPerSeed) {
  const std::string a = generateSceneJson({.targetPolygons = 1000, .seed = 3});
  EXPECT_EQ(a, generateSceneJson({.targetPolygons = 1000, .seed = 3}));
  EXPECT_NE(a, generateSceneJson({.targetPolygons = 1000, .seed = 4}));
}

TEST(SceneGenerator, ManySeedsAndSizesAreValid) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed)
    for (int target : {54, 137, 500, 2345}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + ", target " + std::to_string(target));
      const JsonScene scene =
          parseSceneText(generateSceneJson({.targetPolygons = target, .seed = seed}));
      EXPECT_EQ(scene.polygonCount(), target);
      expectValid(scene);
    }
}

TEST(SceneGenerator, HonoursTheFrameCount) {
  for (int frames : {1, 2, 9}) {
    const JsonScene scene =
        parseSceneText(generateSceneJson({.targetPolygons = 400, .seed = 5, .frames = frames}));
    EXPECT_EQ(scene.frames, frames);
    const JsonObject* box = findObject(scene, "floating-box");
    ASSERT_NE(box, nullptr);
    EXPECT_EQ(int(box->motion.keyframes().size()), frames);
    expectValid(scene);
  }
}

// Several moving boxes (generate --moving-boxes): the exact count still, each box dynamic with
// every keyframe, and the scene valid in every frame (no two objects' boxes share interior).
TEST(SceneGenerator, SeveralMovingBoxes) {
  for (int boxes : {2, 3, 4})
    for (int target : {54, 1000}) {
      SCOPED_TRACE(std::to_string(boxes) + " boxes, target " + std::to_string(target));
      const JsonScene scene = parseSceneText(generateSceneJson(
          {.targetPolygons = target, .seed = 2, .frames = 5, .movingBoxes = boxes}));
      EXPECT_EQ(scene.polygonCount(), std::max(target, 49 + 6 * (boxes - 1)));
      int dynamic = 0;
      for (const JsonObject& o : scene.objects)
        if (o.isDynamic()) {
          ++dynamic;
          EXPECT_EQ(o.motion.keyframes().size(), 5u) << o.name;
        }
      EXPECT_EQ(dynamic, boxes);
      expectValid(scene);
    }
}

// A hundred thousand polygons: the exact count and a valid room. How fast is a benchmark's
// question, not a test's: a wall-clock bound passes or fails with the machine's load.
TEST(SceneGenerator, ScalesToAHundredThousandPolygons) {
  const JsonScene scene = parseSceneText(generateSceneJson({.targetPolygons = 100000, .seed = 1}));
  EXPECT_EQ(scene.polygonCount(), 100000);
  EXPECT_TRUE(findRoomProblems(scene).empty()) << join(findRoomProblems(scene));
  EXPECT_TRUE(findSolidProblems(scene).empty()) << join(findSolidProblems(scene));
}

}  // namespace
}  // namespace penumbra
