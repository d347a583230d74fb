#include "penumbra/render/radiance_mesh.h"

#include <numbers>

#include "penumbra/geometry/triangulation.h"

namespace penumbra {

ColoredMesh radianceMesh(const RadiosityMesh& solution) {
  ColoredMesh mesh;
  mesh.positions = solution.positions;
  mesh.indices = solution.indices;
  mesh.colors.reserve(solution.radiosity.size());
  for (const Rgb& b : solution.radiosity) mesh.colors.push_back(b / std::numbers::pi);
  return mesh;
}

ColoredMesh radianceMesh(const IrradianceMesh& solution, const PosedScene& scene) {
  ColoredMesh mesh;
  mesh.positions = solution.positions;
  mesh.indices = solution.indices;
  mesh.colors.reserve(solution.positions.size());
  for (size_t i = 0; i < solution.positions.size(); ++i) {
    const Material& material = scene.materialOf(scene.polygons[solution.receiverOf[i]]);
    mesh.colors.push_back(material.reflectance * solution.irradiance[i] / std::numbers::pi);
  }
  for (const WorldPolygon& polygon : scene.polygons) {
    if (!polygon.isLight) continue;
    const Rgb radiance = scene.materialOf(polygon).emission / std::numbers::pi;
    const auto first = std::uint32_t(mesh.positions.size());
    for (const Vec3& v : polygon.vertices) {
      mesh.positions.push_back(v);
      mesh.colors.push_back(radiance);
    }
    for (const auto& t : triangulate(polygon.vertices))
      for (int k : t) mesh.indices.push_back(first + std::uint32_t(k));
  }
  return mesh;
}

}  // namespace penumbra
