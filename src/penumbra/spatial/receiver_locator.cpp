#include "penumbra/spatial/receiver_locator.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

std::vector<ReceiverMatch> locateReceivers(const PosedScene& scene, const UniformGrid& grid,
                                           const Vec3& p, const Vec3& n) {
  const double tolerance = kReceiverRelativeTolerance * scene.extent.diagonalLength();
  Box3 around;
  around.extend(p);
  std::vector<ReceiverMatch> found;
  for (PolygonId id : grid.polygonsInBox(around.expanded(tolerance))) {
    const WorldPolygon& polygon = scene.polygons[id];
    if (dot(polygon.plane.normal, n) <= 0) continue;
    const double distance = std::abs(polygon.plane.signedDistance(p));
    if (distance > tolerance) continue;
    const PlaneFrame frame = PlaneFrame::fromPlane(polygon.plane, polygon.vertices[0]);
    Polygon2 loop;
    for (const Vec3& v : polygon.vertices) loop.push_back(frame.toLocal(v));
    const Vec2 q = frame.toLocal(p);
    if (containsPoint(loop, q) || isNearBoundary(loop, q, tolerance))
      found.push_back(ReceiverMatch{id, distance});
  }
  // Stable: among planes equally near, the grid's order decides, as it always has.
  std::stable_sort(found.begin(), found.end(), [](const ReceiverMatch& a, const ReceiverMatch& b) {
    return a.planeDistance < b.planeDistance;
  });
  return found;
}

std::optional<ReceiverMatch> locateReceiver(const PosedScene& scene, const UniformGrid& grid,
                                            const Vec3& p, const Vec3& n) {
  const std::vector<ReceiverMatch> found = locateReceivers(scene, grid, p, n);
  if (found.empty()) return std::nullopt;
  return found.front();
}

}  // namespace penumbra
