#include "penumbra/scene/receiver_sampling.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

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
      total += 0.5 * length(cross(c[1] - c[0], c[2] - c[0]));
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
