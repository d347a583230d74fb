#include "scene_json_writer.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

namespace penumbra::fuzz {

namespace {

using Json = nlohmann::json;

Json vec3(const Vec3& v) {
  return Json::array({v.x, v.y, v.z});
}

Json pose(const TrsPose& pose) {
  Json j = {{"translate", vec3(pose.translate)}, {"scale", vec3(pose.scale)}};
  const Quaternion& q = pose.rotate;
  const double sine = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
  if (sine > 0)
    j["rotate"] = {{"axis", vec3(Vec3{q.x, q.y, q.z} / sine)},
                   {"degrees", 2 * std::atan2(sine, q.w) * 180 / std::numbers::pi}};
  return j;
}

}  // namespace

std::string sceneToJson(const Scene& scene) {
  Json materials = Json::object();
  for (const Material& m : scene.materials)
    materials[m.name] = {{"reflectance", {m.reflectance.r, m.reflectance.g, m.reflectance.b}},
                         {"emission", {m.emission.r, m.emission.g, m.emission.b}}};
  Json objects = Json::array();
  for (const SceneObject& object : scene.objects) {
    // The format gives one material per object: the first polygon's (the structure-aware
    // target's objects have one polygon each).
    Json polygons = Json::array();
    for (const Polygon3& polygon : object.polygons) {
      Json corners = Json::array();
      for (const Vec3& p : polygon) corners.push_back(vec3(p));
      polygons.push_back(corners);
    }
    Json o = {{"name", object.name},
              {"material", scene.materials[object.polygonMaterial.at(0)].name},
              {"polygons", polygons},
              {"transform", pose(object.transform)}};
    if (!object.motion.isEmpty()) {
      Json keys = Json::array();
      for (const Keyframe& k : object.motion.keyframes()) {
        Json key = pose(k.pose);
        key["frame"] = k.frame;
        keys.push_back(key);
      }
      o["motion"] = keys;
    }
    objects.push_back(o);
  }
  return Json{{"penumbra", 1}, {"materials", materials}, {"objects", objects}}.dump(1) + "\n";
}

}  // namespace penumbra::fuzz
