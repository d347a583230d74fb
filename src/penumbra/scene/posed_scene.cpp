#include "penumbra/scene/posed_scene.h"

#include <algorithm>

namespace penumbra {

PosedScene poseAt(const Scene& scene, double frame) {
  PosedScene posed;
  posed.frame = frame;
  posed.materials = scene.materials;
  posed.polygons.reserve(scene.polygonCount());
  for (int objectIndex = 0; objectIndex < int(scene.objects.size()); ++objectIndex) {
    const SceneObject& object = scene.objects[objectIndex];
    const Transform transform = object.transformAt(frame);
    const bool mirrored = transform.isReflection();
    for (size_t k = 0; k < object.polygons.size(); ++k) {
      WorldPolygon wp;
      wp.id = PolygonId(posed.polygons.size());
      wp.objectIndex = objectIndex;
      wp.material = object.polygonMaterial[k];
      wp.vertices.reserve(object.polygons[k].size());
      for (const Vec3& p : object.polygons[k]) wp.vertices.push_back(transform.applyToPoint(p));
      // A mirroring transform flips winding; restore counter-clockwise-from-the-front.
      if (mirrored) std::reverse(wp.vertices.begin(), wp.vertices.end());
      wp.plane = supportingPlane(wp.vertices);
      wp.area = area(wp.vertices);
      wp.bounds = boundingBox(wp.vertices);
      wp.isLight = scene.materials[wp.material].isEmitter();
      if (wp.isLight) posed.lights.push_back(wp.id);
      posed.bounds.extend(wp.bounds);
      posed.polygons.push_back(std::move(wp));
    }
  }
  return posed;
}

}  // namespace penumbra
