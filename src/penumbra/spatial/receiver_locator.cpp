#include "penumbra/spatial/receiver_locator.h"

#include <cmath>

namespace penumbra {

std::optional<ReceiverMatch> locateReceiver(const PosedScene& scene, const UniformGrid& grid,
                                            const Vec3& p, const Vec3& n) {
  const double tolerance = kReceiverRelativeTolerance * scene.extent.diagonalLength();
  Box3 around;
  around.extend(p);
  std::optional<ReceiverMatch> best;
  for (PolygonId id : grid.polygonsInBox(around.expanded(tolerance))) {
    const WorldPolygon& polygon = scene.polygons[id];
    if (dot(polygon.plane.normal, n) <= 0) continue;
    const double distance = std::abs(polygon.plane.signedDistance(p));
    if (distance > tolerance || (best && distance >= best->planeDistance)) continue;
    const PlaneFrame frame = PlaneFrame::fromPlane(polygon.plane, polygon.vertices[0]);
    Polygon2 loop;
    for (const Vec3& v : polygon.vertices) loop.push_back(frame.toLocal(v));
    const Vec2 q = frame.toLocal(p);
    if (containsPoint(loop, q) || isNearBoundary(loop, q, tolerance))
      best = ReceiverMatch{id, distance};
  }
  return best;
}

}  // namespace penumbra
