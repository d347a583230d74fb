#include "penumbra/scene/receiver_sampling.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "penumbra/geometry/polygon.h"
#include "penumbra/geometry/triangulation.h"

namespace penumbra {

std::vector<ReceiverPoint> sampleReceiverPoints(const PosedScene& scene, int count,
                                                std::uint64_t seed) {
  struct Triangle {
    std::array<Vec3, 3> corners;
    PolygonId receiver;
  };
  std::vector<Triangle> triangles;
  std::vector<double> cumulativeArea;
  double total = 0;
  for (const WorldPolygon& polygon : scene.polygons) {
    if (polygon.isLight) continue;
    for (const auto& t : triangulate(polygon.vertices)) {
      const std::array<Vec3, 3> c{polygon.vertices[t[0]], polygon.vertices[t[1]],
                                  polygon.vertices[t[2]]};
      total += triangleArea(c[0], c[1], c[2]);
      cumulativeArea.push_back(total);
      triangles.push_back({c, polygon.id});
    }
  }
  std::vector<ReceiverPoint> points;
  if (triangles.empty()) return points;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0, 1);
  points.reserve(count);
  for (int i = 0; i < count; ++i) {
    const size_t k =
        std::lower_bound(cumulativeArea.begin(), cumulativeArea.end(), uniform(rng) * total) -
        cumulativeArea.begin();
    const Triangle& t = triangles[std::min(k, triangles.size() - 1)];
    // Uniform in the triangle: square-root warp of the first coordinate.
    const double r1 = std::sqrt(uniform(rng)), r2 = uniform(rng);
    const Vec3 p =
        t.corners[0] * (1 - r1) + t.corners[1] * (r1 * (1 - r2)) + t.corners[2] * (r1 * r2);
    points.push_back({p, scene.polygons[t.receiver].plane.normal, t.receiver});
  }
  return points;
}

}  // namespace penumbra

namespace penumbra {

std::vector<ReceiverPoint> vertexShadowPoints(const PosedScene& scene, PolygonId receiver,
                                              double step) {
  const WorldPolygon& r = scene.polygons[receiver];
  const PlaneFrame frame = PlaneFrame::fromPlane(r.plane, r.vertices[0]);
  Polygon2 loop;
  for (const Vec3& v : r.vertices) loop.push_back(frame.toLocal(v));
  std::vector<ReceiverPoint> points;
  for (PolygonId light : scene.lights)
    for (const Vec3& corner : scene.polygons[light].vertices) {
      const double height = r.plane.signedDistance(corner);
      if (!(height > 0)) continue;  // the receiver's front faces away from this corner
      for (const WorldPolygon& q : scene.polygons) {
        if (q.id == receiver || q.id == light) continue;
        for (const Vec3& v : q.vertices) {
          const double drop = height - r.plane.signedDistance(v);
          if (!(drop > 0)) continue;  // v is not between the corner and the receiver's plane
          const Vec2 hit = frame.toLocal(corner + (v - corner) * (height / drop));
          for (const Vec2 offset :
               {Vec2{0, 0}, Vec2{step, 0}, Vec2{-step, 0}, Vec2{0, step}, Vec2{0, -step}}) {
            const Vec2 x = hit + offset;
            if (containsPoint(loop, x)) points.push_back({frame.toWorld(x), r.plane.normal, r.id});
          }
        }
      }
    }
  return points;
}

}  // namespace penumbra
