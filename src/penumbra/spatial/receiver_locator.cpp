#include "penumbra/spatial/receiver_locator.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

// Calls visit(match) for every polygon that contains p within the tolerance and faces n, in the
// grid's order.
template <class Visit>
void forEachReceiver(const PosedScene& scene, const UniformGrid& grid, const Vec3& p, const Vec3& n,
                     Visit&& visit) {
  const double tolerance = kReceiverRelativeTolerance * scene.extent.diagonalLength();
  Box3 around;
  around.extend(p);
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
      visit(ReceiverMatch{id, distance});
  }
}

}  // namespace

std::vector<ReceiverMatch> locateReceivers(const PosedScene& scene, const UniformGrid& grid,
                                           const Vec3& p, const Vec3& n) {
  std::vector<ReceiverMatch> found;
  forEachReceiver(scene, grid, p, n, [&](const ReceiverMatch& m) { found.push_back(m); });
  // Stable: among planes equally near, the grid's order decides, as locateReceiver's does.
  std::stable_sort(found.begin(), found.end(), [](const ReceiverMatch& a, const ReceiverMatch& b) {
    return a.planeDistance < b.planeDistance;
  });
  return found;
}

std::optional<ReceiverMatch> locateReceiver(const PosedScene& scene, const UniformGrid& grid,
                                            const Vec3& p, const Vec3& n) {
  // The first of the nearest planes, without collecting the others (probes of every engine).
  std::optional<ReceiverMatch> best;
  forEachReceiver(scene, grid, p, n, [&](const ReceiverMatch& m) {
    if (!best || m.planeDistance < best->planeDistance) best = m;
  });
  return best;
}

}  // namespace penumbra
