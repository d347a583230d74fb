// validateScene on what the engines see: polygons in world coordinates at every transform and
// keyframe, and scales that interpolate through zero between keyframes. Each case was a crash of
// the engines on a file the loaders accepted, found by fuzz/ (fuzz/README.md, "Fixed findings").

#include <gtest/gtest.h>

#include <string>

#include "penumbra/base/input_error.h"
#include "penumbra/scene/posed_scene.h"
#include "penumbra/scene/scene_loader.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

// A lamp and a floor, then `object` (a JSON object of the "objects" array).
std::string sceneWith(const std::string& object) {
  return R"({ "penumbra": 1,
  "materials": { "white": { "reflectance": [0.5, 0.5, 0.5] },
                 "lamp": { "emission": [10, 10, 10] } },
  "objects": [
    { "material": "lamp", "polygons": [ [[0, 0, 2], [0, 1, 2], [1, 1, 2], [1, 0, 2]] ] },
    { "material": "white", "polygons": [ [[-2, -2, 0], [2, -2, 0], [2, 2, 0], [-2, 2, 0]] ] },
    )" + object +
         " ] }";
}

// loadScene(path) throws an InputError whose location and message contain the fragments.
void expectInputError(const std::string& path, const std::string& location,
                      std::initializer_list<std::string> fragments) {
  try {
    loadScene(path);
    ADD_FAILURE() << "no InputError for " << path;
  } catch (const InputError& e) {
    EXPECT_NE(e.location().find(location), std::string::npos) << e.what();
    for (const std::string& fragment : fragments)
      EXPECT_NE(e.problem().find(fragment), std::string::npos)
          << "'" << fragment << "' missing from: " << e.what();
  }
}

// A quad 1e-9 across, valid in its own coordinates, scaled by 1e-6 and moved 1000 away: its
// corners round together in world coordinates (the discontinuity mesh got a NaN plane, and CGAL's
// exact numbers aborted the process with SIGFPE).
TEST(SceneValidation, PolygonDegenerateInWorldCoordinatesIsRefused) {
  test::TempDir dir;
  const std::string path = dir.write("tiny.json", sceneWith(R"({ "material": "white",
      "polygons": [ [[0, 0, 1], [1e-9, 0, 1], [1e-9, 1e-9, 1], [0, 1e-9, 1]] ],
      "transform": { "translate": [0, 1000, 1000], "scale": [1e-6, 1e-6, 1e-6] } })"));
  expectInputError(path, "tiny.json: /objects/2/polygons/0",
                   {"in world coordinates", "after the object's transform"});
}

// The same check at every keyframe: a non-uniform scale that squashes a triangle flat there.
TEST(SceneValidation, PolygonSquashedAtAKeyframeIsRefused) {
  test::TempDir dir;
  const std::string path = dir.write("squashed.json", sceneWith(R"({ "material": "white",
      "polygons": [ [[0, 0, 1], [1, 0, 1], [0, 1, 1]] ],
      "motion": [ { "frame": 0 }, { "frame": 1, "scale": [1e-6, 1e6, 1] } ] })"));
  expectInputError(path, "squashed.json: /objects/2/polygons/0",
                   {"zero area", "after the object's pose at keyframe 1"});
}

// Scales interpolate linearly: from 1 to -1 over frames 0..2, frame 1 has scale 0 and the object
// collapses (every polygon of zero area there), though both keyframes are valid.
TEST(SceneValidation, ScaleChangingSignBetweenKeyframesIsRefused) {
  test::TempDir dir;
  const std::string path = dir.write("flip.json", sceneWith(R"({ "name": "flipper",
      "material": "white", "polygons": [ [[0, 0, 1], [1, 0, 1], [0, 1, 1]] ],
      "motion": [ { "frame": 0 }, { "frame": 2, "scale": [-1, 1, 1] } ] })"));
  expectInputError(path, "flip.json: object 'flipper' keyframes 0 and 2", {"changes sign"});
}

// What stays legal: a mirroring scale held over the whole motion, a large translation of a polygon
// of ordinary size, and a small scale of a polygon that stays far above rounding.
TEST(SceneValidation, OrdinaryTransformsStillLoad) {
  test::TempDir dir;
  const std::string path = dir.write("fine.json", sceneWith(R"({ "material": "white",
      "polygons": [ [[0, 0, 1], [1, 0, 1], [0, 1, 1]] ],
      "motion": [ { "frame": 0, "scale": [-1, 1, 1], "translate": [1e6, 0, 0] },
                  { "frame": 2, "scale": [-1e-3, 1e-3, 1e-3] } ] })"));
  const Scene scene = loadScene(path);
  EXPECT_EQ(scene.frames, 3);
  EXPECT_GT(poseAt(scene, 1).polygons[2].area, 0);
}

}  // namespace
}  // namespace penumbra
