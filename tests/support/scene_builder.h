#pragma once
// Builds small scenes in code for tests: named materials, polygons (optionally grouped into
// objects), then poses them. Test-only; real scenes come from the loaders.

#include <map>
#include <string>

#include "penumbra/scene/posed_scene.h"

namespace penumbra::test {

class SceneBuilder {
 public:
  SceneBuilder& addMaterial(const std::string& name, const Rgb& reflectance,
                            const Rgb& emission = {}) {
    materialIndex_[name] = int(scene_.materials.size());
    scene_.materials.push_back({name, reflectance, emission, false});
    return *this;
  }
  // Adds a polygon as an object of its own unless `object` names an existing one.
  SceneBuilder& addPolygon(const std::string& material, const Polygon3& polygon,
                           const std::string& object = "") {
    int index = -1;
    for (size_t i = 0; i < scene_.objects.size() && !object.empty(); ++i)
      if (scene_.objects[i].name == object) index = int(i);
    if (index < 0) {
      scene_.objects.push_back({});
      scene_.objects.back().name =
          object.empty() ? "polygon " + std::to_string(scene_.polygonCount()) : object;
      index = int(scene_.objects.size()) - 1;
    }
    SceneObject& o = scene_.objects[index];
    o.polygons.push_back(polygon);
    o.polygonMaterial.push_back(materialIndex_.at(material));
    o.polygonOrigin.push_back("test polygon " + std::to_string(scene_.polygonCount()));
    return *this;
  }
  Scene& scene() { return scene_; }
  PosedScene pose(double frame = 0) const { return poseAt(scene_, frame); }

 private:
  Scene scene_;
  std::map<std::string, int> materialIndex_;
};

}  // namespace penumbra::test
