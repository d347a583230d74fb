#include "scene_file_check.h"

#include <cmath>
#include <optional>
#include <set>
#include <vector>

#include "fuzz_outcome.h"
#include "penumbra/scene/closedness.h"
#include "penumbra/scene/posed_scene.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra::fuzz {

namespace {

// The largest frame count the JSON loader admits (its kMaxFrame + 1); glTF's sampled animations
// stay far below it.
constexpr int kMaxFrames = 1'000'001;

bool isWithinReach(const Vec3& p) {
  return std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate &&
         std::abs(p.z) <= kMaxCoordinate;
}

// What validateScene promises of every pose: finite polygons of at least 3 corners within
// kMaxCoordinate, each with a unit normal and a positive area.
void checkPose(const PosedScene& posed, int frame) {
  const std::string at = " at frame " + std::to_string(frame);
  for (const WorldPolygon& polygon : posed.polygons) {
    const std::string which = "posed polygon " + std::to_string(polygon.id) + at;
    if (polygon.vertices.size() < 3) reportFinding(which + " has fewer than 3 corners");
    for (const Vec3& p : polygon.vertices)
      if (!p.isFinite() || !isWithinReach(p))
        reportFinding(which + " has a corner that is not finite or beyond kMaxCoordinate");
    const double normalLength = length(polygon.plane.normal);
    if (!(std::abs(normalLength - 1) <= 1e-9))
      reportFinding(which + " has a plane normal of length " + std::to_string(normalLength));
    if (!(polygon.area > 0) || !std::isfinite(polygon.area))
      reportFinding(which + " has area " + std::to_string(polygon.area));
  }
}

// The first and last frames, and the integer frames half way between consecutive keyframes of
// each object (where interpolation is furthest from what validation checked), at most 64.
std::vector<int> framesToPose(const Scene& scene) {
  std::set<int> frames = {0, scene.frames - 1};
  for (const SceneObject& object : scene.objects) {
    const std::vector<Keyframe>& keys = object.motion.keyframes();
    for (size_t i = 1; i < keys.size() && frames.size() < 64; ++i)
      frames.insert((keys[i - 1].frame + keys[i].frame) / 2);
  }
  return {frames.begin(), frames.end()};
}

}  // namespace

void checkSceneFile(const std::string& path, const std::string& mustMention) {
  std::optional<Scene> scene;
  if (!succeedsOrRejects(mustMention, [&] { scene = loadScene(path); })) return;
  noteOutcome("accepted: " + std::to_string(scene->polygonCount()) + " polygons, " +
              std::to_string(scene->frames) + " frames");
  if (scene->polygonCount() <= 0) reportFinding("a loaded scene has no polygons");
  if (scene->frames < 1 || scene->frames > kMaxFrames)
    reportFinding("a loaded scene has " + std::to_string(scene->frames) + " frames");
  // Nothing after loading may throw, not even an InputError: the scene was accepted.
  try {
    for (const int frame : framesToPose(*scene)) {
      const PosedScene posed = poseAt(*scene, frame);
      checkPose(posed, frame);
      if (frame == 0) checkClosedness(*scene, posed);
    }
  } catch (const std::exception& e) {
    reportFinding("an accepted scene failed after loading: " + describe(e));
  }
}

}  // namespace penumbra::fuzz
