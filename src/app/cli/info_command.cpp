// `penumbra info SCENE`: counts, bounds and closedness of a scene.

#include <cstdio>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "frame_range.h"
#include "penumbra/scene/closedness.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra::cli {

int runInfo(const InfoOptions& options, const CommonOptions&) {
  const Scene scene = loadScene(options.scene);
  const int frame = options.frame.value_or(0);
  checkFrame(frame, scene.frames);
  const PosedScene posed = poseAt(scene, frame);
  const ClosednessReport closedness = checkClosedness(scene, posed);
  // Bounds over all frames (every pose the keyframes reach, conservative between keyframes that
  // rotate): what a moving object sweeps matters to grids and shafts.
  const Box3& allFrames = posed.extent;

  std::vector<std::string> openObjects;
  for (const ObjectClosedness& c : closedness.objects)
    if (!c.isClosed) openObjects.push_back(scene.objects[c.objectIndex].name);

  if (options.json) {
    nlohmann::json j;
    j["scene"] = options.scene;
    j["polygons"] = posed.polygons.size();
    j["lights"] = posed.lights.size();
    j["objects"] = scene.objects.size();
    j["dynamic_objects"] = scene.dynamicObjectCount();
    j["frames"] = scene.frames;
    j["materials"] = scene.materials.size();
    j["bounds"] = {{"min", {posed.bounds.min.x, posed.bounds.min.y, posed.bounds.min.z}},
                   {"max", {posed.bounds.max.x, posed.bounds.max.y, posed.bounds.max.z}}};
    j["bounds_all_frames"] = {{"min", {allFrames.min.x, allFrames.min.y, allFrames.min.z}},
                              {"max", {allFrames.max.x, allFrames.max.y, allFrames.max.z}}};
    j["closed"] = closedness.isSceneClosed;
    j["open_objects"] = openObjects;
    std::printf("%s\n", j.dump(2).c_str());
    return kOk;
  }
  std::printf("scene            %s\n", options.scene.c_str());
  std::printf("polygons         %zu\n", posed.polygons.size());
  std::printf("lights           %zu\n", posed.lights.size());
  std::printf("objects          %zu (%d dynamic)\n", scene.objects.size(),
              scene.dynamicObjectCount());
  std::printf("frames           %d\n", scene.frames);
  std::printf("materials        %zu\n", scene.materials.size());
  std::printf("bounds (frame %d) [%g, %g, %g] .. [%g, %g, %g]\n", frame, posed.bounds.min.x,
              posed.bounds.min.y, posed.bounds.min.z, posed.bounds.max.x, posed.bounds.max.y,
              posed.bounds.max.z);
  std::printf("bounds (frames)  [%g, %g, %g] .. [%g, %g, %g]\n", allFrames.min.x, allFrames.min.y,
              allFrames.min.z, allFrames.max.x, allFrames.max.y, allFrames.max.z);
  // The scene's closedness is of the whole; objects open by themselves (a room's walls, closed
  // by its floor) are listed under their own heading, so that "yes" is not read as contradicted.
  if (closedness.isSceneClosed)
    std::printf("closed           yes (every edge of the scene is shared by two polygons)\n");
  else
    std::printf("closed           no (%d open edges, length %g)\n", closedness.sceneOpenEdgeCount,
                closedness.sceneOpenEdgeLength);
  if (!openObjects.empty())
    std::printf("open objects     %zu, each open by itself%s:\n", openObjects.size(),
                closedness.isSceneClosed ? " (closed by the others)" : "");
  for (const ObjectClosedness& c : closedness.objects)
    if (!c.isClosed)
      std::printf("  %s: %d open edges, length %g\n", scene.objects[c.objectIndex].name.c_str(),
                  c.openEdgeCount, c.openEdgeLength);
  return kOk;
}

}  // namespace penumbra::cli
