#include "penumbra/volumes/mirror_planes.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

Transform reflectionThrough(const Plane& plane) {
  const Vec3& n = plane.normal;
  Transform t;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t.linear.m[i][j] = (i == j ? 1.0 : 0.0) - 2 * n[i] * n[j];
  t.translation = n * (2 * plane.offset);
  return t;
}

bool liesInPlane(const WorldPolygon& polygon, const Plane& plane, double tolerance) {
  return std::all_of(polygon.vertices.begin(), polygon.vertices.end(),
                     [&](const Vec3& v) { return std::abs(plane.signedDistance(v)) <= tolerance; });
}

std::vector<MirrorPlane> findMirrorPlanes(const PosedScene& scene) {
  // Relative to the scene so that millimetre and kilometre scenes group alike; mirror polygons
  // of one wall cut by a modeller lie in one plane to far better than this.
  const double tolerance = 1e-9 * std::max(scene.extent.diagonalLength(), 1e-300);
  std::vector<MirrorPlane> groups;
  for (const WorldPolygon& polygon : scene.polygons) {
    const Material& material = scene.materialOf(polygon);
    if (!material.mirror || polygon.isLight) continue;
    auto same = [&](const MirrorPlane& g) {
      const WorldPolygon& first = scene.polygons[g.polygons.front()];
      return first.material == polygon.material &&
             dot(g.plane.normal, polygon.plane.normal) >= 1 - 1e-9 &&
             liesInPlane(polygon, g.plane, tolerance);
    };
    auto group = std::find_if(groups.begin(), groups.end(), same);
    if (group == groups.end()) {
      groups.push_back({polygon.plane, reflectionThrough(polygon.plane), material.reflectance, {}});
      group = groups.end() - 1;
    }
    group->polygons.push_back(polygon.id);
  }
  return groups;
}

}  // namespace penumbra
