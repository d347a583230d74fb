#include <cmath>

#include "penumbra/base/input_error.h"
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
  }
  if (scene.polygonCount() == 0) throw InputError(scene.sourcePath, "the scene has no polygons");
}

}  // namespace penumbra
