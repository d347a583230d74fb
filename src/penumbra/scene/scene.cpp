#include "penumbra/scene/scene.h"

namespace penumbra {

int Scene::polygonCount() const {
  int count = 0;
  for (const SceneObject& o : objects) count += int(o.polygons.size());
  return count;
}

int Scene::dynamicObjectCount() const {
  int count = 0;
  for (const SceneObject& o : objects) count += o.isDynamic() ? 1 : 0;
  return count;
}

std::vector<PolygonId> Scene::objectPolygonOffsets() const {
  std::vector<PolygonId> offsets{0};
  for (const SceneObject& o : objects) offsets.push_back(offsets.back() + int(o.polygons.size()));
  return offsets;
}

}  // namespace penumbra
