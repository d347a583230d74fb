#pragma once
// Independent checks of scene JSON text (DESIGN.md §4) for the bundled scenes and the scene
// generator. They parse with nlohmann directly rather than through the project's loader, so
// that the scene files and the loader are tested against the format, not against each other.
//
// Conventions the checked scenes follow (scripts/make-bundled-scenes.py, scene_generator.cpp):
//  * the room shell is the union of the objects named "room" or "room-*";
//  * every other object is a union of closed convex solids, recovered as the components of
//    polygons connected through shared vertices (so distinct solids never share a vertex);
//  * lights are open: single polygons.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "penumbra/geometry/polygon.h"
#include "penumbra/scene/motion.h"

namespace penumbra::scene_checks {

struct JsonObject {
  std::string name;
  bool emitter = false;
  bool room = false;
  std::vector<Polygon3> polygons;  // object coordinates
  TrsPose placement;               // the static "transform"
  Motion motion;                   // empty for static objects

  bool isDynamic() const { return !motion.isEmpty(); }
  TrsPose poseAt(double frame) const { return isDynamic() ? motion.poseAt(frame) : placement; }
};

struct JsonScene {
  std::vector<JsonObject> objects;
  int frames = 1;
  Vec3 eye, target, up;
  double fovYDegrees = 0;
  int width = 0, height = 0;

  int polygonCount() const;
};

// Parses the scene (inline "polygons" only). Throws std::runtime_error on anything unexpected,
// including keys outside §4.
JsonScene parseScene(const nlohmann::json& json);
JsonScene parseSceneText(const std::string& text);
JsonScene parseSceneFile(const std::string& path);

// Each check returns human-readable problems; empty means it passed.

// findPolygonDefect on every polygon, in world space at frame 0.
std::vector<std::string> findPolygonProblems(const JsonScene& scene);
// The room shell is closed (each directed edge matched by exactly one reversed edge) and every
// shell polygon faces the room's centre.
std::vector<std::string> findRoomProblems(const JsonScene& scene);
// Every other non-emitting object splits into closed, convex, outward-oriented solids.
std::vector<std::string> findSolidProblems(const JsonScene& scene);
// Lights face into the room, lie inside it and keep clear of every solid at all frames.
std::vector<std::string> findLightProblems(const JsonScene& scene);
// No two solids share interior at any frame or between frames (touching is allowed); every
// solid stays inside the room. With `objectBoxes`, also the bounding boxes of distinct objects
// have disjoint interiors at every frame.
std::vector<std::string> findOverlapProblems(const JsonScene& scene, bool objectBoxes);
// The eye is inside the room and outside every solid, and every dynamic object's centre is in
// the field of view at frame 0.
std::vector<std::string> findCameraProblems(const JsonScene& scene);

// The smallest gap between the named object's solids and any other solid over its keyframe
// frames (a lower bound of the distance, exact for axis-aligned boxes apart along one axis).
double closestApproach(const JsonScene& scene, const std::string& objectName);

}  // namespace penumbra::scene_checks
