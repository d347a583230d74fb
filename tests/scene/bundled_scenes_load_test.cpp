// Every bundled scene loads through the project's loader, passes validation, and is closed; the
// generator's output loads too.

#include <gtest/gtest.h>

#include <filesystem>

#include "penumbra/scene/closedness.h"
#include "penumbra/scene/scene_generator.h"
#include "penumbra/scene/scene_loader.h"
#include "support/temp_dir.h"

namespace penumbra {
namespace {

std::vector<std::string> bundledScenes() {
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(
           std::string(PENUMBRA_SOURCE_DIR) + "/scenes")) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".json" || ext == ".gltf" || ext == ".glb") paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

TEST(BundledScenes, LoadValidateAndAreClosedInEveryFrame) {
  const std::vector<std::string> paths = bundledScenes();
  ASSERT_GE(paths.size(), 7u);
  for (const std::string& path : paths) {
    SCOPED_TRACE(path);
    const Scene scene = loadScene(path);
    EXPECT_GE(scene.polygonCount(), 1);
    for (int frame = 0; frame < scene.frames; ++frame) {
      const PosedScene posed = poseAt(scene, frame);
      EXPECT_FALSE(posed.lights.empty());
      const ClosednessReport closedness = checkClosedness(scene, posed);
      EXPECT_TRUE(closedness.isSceneClosed) << "frame " << frame;
    }
  }
}

TEST(BundledScenes, DeskPolygonCounts) {
  const std::string dir = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/office-desk/";
  EXPECT_EQ(loadScene(dir + "desk-145.json").polygonCount(), 145);
  EXPECT_EQ(loadScene(dir + "desk-307.json").polygonCount(), 307);
  EXPECT_EQ(loadScene(dir + "desk-475.json").polygonCount(), 475);
  EXPECT_EQ(loadScene(dir + "desk-145-close.json").polygonCount(), 145);
}

TEST(GeneratedScenes, LoadAndAreClosed) {
  test::TempDir dir;
  for (int polygons : {100, 1000, 10000}) {
    const std::string path = dir.write("generated-" + std::to_string(polygons) + ".json",
                                       generateSceneJson({polygons, 3, 4}));
    const Scene scene = loadScene(path);
    EXPECT_EQ(scene.polygonCount(), polygons);  // the generator's exact count (the bound was 2%)
    EXPECT_EQ(scene.dynamicObjectCount(), 1);
    const PosedScene posed = poseAt(scene, 2);
    EXPECT_TRUE(checkClosedness(scene, posed).isSceneClosed);
  }
}

}  // namespace
}  // namespace penumbra
