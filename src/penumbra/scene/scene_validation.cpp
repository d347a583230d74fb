#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "penumbra/base/input_error.h"
#include "penumbra/scene/reach_bounds.h"
#include "penumbra/scene/scene_loader.h"

namespace penumbra {

namespace {

void validateMaterial(const Scene& scene, const Material& m) {
  const auto bad = [&](const std::string& what) {
    throw InputError(scene.sourcePath, "material '" + m.name + "': " + what);
  };
  if (!m.reflectance.isFinite() || !m.emission.isFinite()) bad("non-finite value");
  for (double c : {m.reflectance.r, m.reflectance.g, m.reflectance.b})
    if (c < 0 || c > 1) bad("reflectance must lie in [0, 1] per channel");
  for (double c : {m.emission.r, m.emission.g, m.emission.b})
    if (c < 0) bad("emission must be non-negative");
}

void validatePose(const std::string& where, const TrsPose& pose) {
  const Transform t = pose.toTransform();
  if (!t.translation.isFinite() || !t.isInvertible() || !std::isfinite(t.linear.determinant()))
    throw InputError(where, "transform is not finite and invertible");
}

std::string shortNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}
std::string magnitude() {
  return shortNumber(kMaxCoordinate);
}

// Every pose the object reaches (its keyframes, conservatively between them) stays within
// kMaxCoordinate of the origin, and its scale keeps a polygon's size within twelve orders of
// magnitude of what was modelled (a glTF scale of 1e-30 collapsed polygons to points).
void validateReach(const std::string& where, const SceneObject& object) {
  const auto scaleOk = [](const TrsPose& pose) {
    for (double s : {pose.scale.x, pose.scale.y, pose.scale.z})
      if (!(std::abs(s) >= 1e-6 && std::abs(s) <= 1e6)) return false;
    return true;
  };
  if (!scaleOk(object.transform))
    throw InputError(where, "scale must lie within 1e-6 and 1e6 in magnitude per axis");
  for (const Keyframe& k : object.motion.keyframes())
    if (!scaleOk(k.pose))
      throw InputError(where + " keyframe " + std::to_string(k.frame),
                       "scale must lie within 1e-6 and 1e6 in magnitude per axis");
  // Scales interpolate linearly between keyframes: one that changes sign passes through 0, where
  // the object is flattened to nothing (every polygon of zero area at some frame in between).
  const std::vector<Keyframe>& keys = object.motion.keyframes();
  for (size_t i = 1; i < keys.size(); ++i)
    for (int axis = 0; axis < 3; ++axis)
      if (keys[i - 1].pose.scale[axis] * keys[i].pose.scale[axis] < 0)
        throw InputError(where + " keyframes " + std::to_string(keys[i - 1].frame) + " and " +
                             std::to_string(keys[i].frame),
                         "scale changes sign between them, so it passes through 0 (the object "
                         "collapses) in between");
  const Box3 reach = reachBounds(object);
  for (const Vec3& corner : {reach.min, reach.max})
    for (double c : {corner.x, corner.y, corner.z})
      if (!(std::abs(c) <= kMaxCoordinate))
        throw InputError(where, "reaches beyond " + magnitude() +
                                    " of the origin in some pose (a coordinate of " +
                                    shortNumber(c) + "); scenes are bounded by " + magnitude() +
                                    " in every frame");
}

bool isIdentity(const TrsPose& pose) {
  return pose.translate == Vec3{} && pose.scale == Vec3{1, 1, 1} && pose.rotate.w == 1 &&
         pose.rotate.x == 0 && pose.rotate.y == 0 && pose.rotate.z == 0;
}

// The engines see polygons in world coordinates, where one valid in its object's coordinates may
// not be: a transform that makes it 1e-15 across 1000 away from the origin rounds its corners
// together (zero area, a NaN plane: CGAL's exact numbers aborted on it), a non-uniform scale
// squashes it flat. Every polygon is checked as posed at the object's transform, or at each of
// its keyframes (the poses between them interpolate these).
void validateWorldPolygons(const SceneObject& object) {
  std::vector<std::pair<std::string, TrsPose>> poses;
  if (object.isDynamic()) {
    for (const Keyframe& k : object.motion.keyframes())
      poses.push_back({"pose at keyframe " + std::to_string(k.frame), k.pose});
  } else if (!isIdentity(object.transform)) {
    poses.push_back({"transform", object.transform});
  }
  Polygon3 world;
  for (const auto& [what, pose] : poses) {
    const Transform transform = pose.toTransform();
    for (size_t i = 0; i < object.polygons.size(); ++i) {
      world.clear();
      for (const Vec3& p : object.polygons[i]) world.push_back(transform.applyToPoint(p));
      if (auto defect = findPolygonDefect(world))
        throw InputError(object.polygonOrigin[i],
                         *defect + " (in world coordinates, after the object's " + what + ")");
    }
  }
}

}  // namespace

void validateScene(const Scene& scene) {
  for (const Material& m : scene.materials) validateMaterial(scene, m);
  for (const SceneObject& object : scene.objects) {
    const std::string objectWhere = scene.sourcePath + ": object '" + object.name + "'";
    if (object.polygonMaterial.size() != object.polygons.size() ||
        object.polygonOrigin.size() != object.polygons.size())
      throw InputError(objectWhere, "internal: per-polygon data out of step");
    validatePose(objectWhere, object.transform);
    for (const Keyframe& k : object.motion.keyframes())
      validatePose(objectWhere + " keyframe " + std::to_string(k.frame), k.pose);
    for (size_t i = 0; i < object.polygons.size(); ++i) {
      if (object.polygonMaterial[i] < 0 || object.polygonMaterial[i] >= int(scene.materials.size()))
        throw InputError(object.polygonOrigin[i], "internal: material index out of range");
      if (auto defect = findPolygonDefect(object.polygons[i]))
        throw InputError(object.polygonOrigin[i], *defect);
    }
    validateReach(objectWhere, object);
    validateWorldPolygons(object);
  }
  if (scene.camera)
    for (const Vec3& p : {scene.camera->eye, scene.camera->target})
      if (!(std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate &&
            std::abs(p.z) <= kMaxCoordinate))
        throw InputError(scene.sourcePath, "the camera lies beyond " + magnitude() +
                                               " of the origin (at " + shortNumber(p.x) + " " +
                                               shortNumber(p.y) + " " + shortNumber(p.z) + ")");
  if (scene.polygonCount() == 0) throw InputError(scene.sourcePath, "the scene has no polygons");
}

}  // namespace penumbra
