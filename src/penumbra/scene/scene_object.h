#pragma once
// An object of the scene: polygons in object coordinates, one material per polygon, a static
// transform, and optional keyframed motion that replaces the static transform when present.

#include <string>
#include <vector>

#include "penumbra/geometry/polygon.h"
#include "penumbra/scene/motion.h"

namespace penumbra {

struct SceneObject {
  std::string name;
  std::vector<Polygon3> polygons;    // object space, counter-clockwise seen from the front
  std::vector<int> polygonMaterial;  // index into Scene::materials, one per polygon
  std::vector<std::string> polygonOrigin;  // where each polygon came from (file:line), for errors
  TrsPose transform;                 // used when motion is empty
  Motion motion;

  bool isDynamic() const { return !motion.isEmpty(); }
  Transform transformAt(double frame) const {
    return isDynamic() ? motion.poseAt(frame).toTransform() : transform.toTransform();
  }
};

}  // namespace penumbra
