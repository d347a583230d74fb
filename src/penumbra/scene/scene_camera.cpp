#include "penumbra/scene/scene_camera.h"

#include <cmath>
#include <numbers>

namespace penumbra {

Camera sceneCamera(const Scene& scene, const PosedScene& posed) {
  if (scene.camera) return *scene.camera;
  Camera c;
  const Vec3 center = posed.extent.center();
  const double radius = posed.extent.diagonalLength() / 2;
  c.target = center;
  c.eye = center + Vec3{0, 0, radius / std::tan(c.fovYDegrees * std::numbers::pi / 360) * 1.1};
  return c;
}

}  // namespace penumbra
