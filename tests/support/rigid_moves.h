#pragma once
// Rigid moves off a scene's keyframes for the update tests: an object turned about the vertical
// through its centre and shifted, composed with its pose now.

#include "penumbra/geometry/transform.h"
#include "penumbra/spatial/dynamic_scene.h"

namespace penumbra::test {

// The object's pose after turning it by `radians` about the vertical axis through the centre of
// its polygons' bounds at the live pose, then shifting it by `shift`.
inline Transform turnedAbout(const DynamicScene& live, int object, double radians,
                             const Vec3& shift) {
  const PosedScene& posed = live.posed();
  Box3 box;
  for (PolygonId id = posed.objectFirstPolygon[object]; id < posed.objectFirstPolygon[object + 1];
       ++id)
    box.extend(posed.polygons[id].bounds);
  const Vec3 c = box.center();
  const Quaternion q = Quaternion::fromAxisAngle({0, 1, 0}, radians);
  return Transform::fromTrs(c + shift - q.toMatrix() * c, q, {1, 1, 1}) * live.transformOf(object);
}

// The scene's emitting object and its (last) moving object; -1 where there is none.
inline std::pair<int, int> lightAndMovingObject(const Scene& scene) {
  int light = -1, moving = -1;
  for (int o = 0; o < int(scene.objects.size()); ++o) {
    for (int m : scene.objects[o].polygonMaterial)
      if (scene.materials[m].isEmitter()) light = o;
    if (scene.objects[o].isDynamic()) moving = o;
  }
  return {light, moving};
}

}  // namespace penumbra::test
