#include "penumbra/spatial/receiver_locator.h"

#include <cmath>

namespace penumbra {

namespace {

// Distance from q to the 2D loop's boundary, and whether q is inside (even-odd).
bool isInsideWithin(const Polygon2& loop, const Vec2& q, double tolerance) {
  if (containsPoint(loop, q)) return true;
  for (size_t i = 0; i < loop.size(); ++i) {
    const Vec2 a = loop[i], b = loop[(i + 1) % loop.size()];
    const Vec2 ab = b - a;
    const double t = std::clamp(dot(q - a, ab) / dot(ab, ab), 0.0, 1.0);
    const Vec2 d = q - (a + ab * t);
    if (dot(d, d) <= tolerance * tolerance) return true;
  }
  return false;
}

}  // namespace

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
    if (isInsideWithin(loop, frame.toLocal(p), tolerance)) best = ReceiverMatch{id, distance};
  }
  return best;
}

}  // namespace penumbra
