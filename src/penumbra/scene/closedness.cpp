#include "penumbra/scene/closedness.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace penumbra {

namespace {

struct DirectedEdge {
  Vec3 a, b;
};

// Edges that lie on one line, keyed by a quantized canonical form of the line.
using LineKey = std::tuple<long long, long long, long long, long long, long long, long long>;

LineKey lineKey(const Vec3& a, const Vec3& b, double tolerance) {
  Vec3 d = normalize(b - a);
  // Canonical direction: first non-negligible component positive.
  const int axis = dominantAxis(d);
  if (d[axis] < 0) d = -d;
  const Vec3 closest = a - d * dot(a, d);  // point of the line nearest the origin
  const auto q = [](double v, double step) { return (long long)std::llround(v / step); };
  constexpr double kDirectionStep = 1e-9;
  return {q(d.x, kDirectionStep),  q(d.y, kDirectionStep),  q(d.z, kDirectionStep),
          q(closest.x, tolerance), q(closest.y, tolerance), q(closest.z, tolerance)};
}

ObjectClosedness checkChain(int objectIndex, const std::vector<const WorldPolygon*>& polygons,
                            double tolerance) {
  std::map<LineKey, std::vector<DirectedEdge>> lines;
  for (const WorldPolygon* polygon : polygons) {
    const Polygon3& v = polygon->vertices;
    for (size_t i = 0; i < v.size(); ++i) {
      const Vec3& a = v[i];
      const Vec3& b = v[(i + 1) % v.size()];
      if (distance(a, b) <= tolerance) continue;
      lines[lineKey(a, b, tolerance)].push_back({a, b});
    }
  }
  ObjectClosedness result;
  result.objectIndex = objectIndex;
  for (const auto& [key, edges] : lines) {
    // Net winding along the line: +1 inside forward edges, -1 inside backward ones.
    const Vec3 origin = edges.front().a;
    const Vec3 dir = normalize(edges.front().b - edges.front().a);
    std::vector<std::pair<double, int>> events;
    for (const DirectedEdge& e : edges) {
      double s = dot(e.a - origin, dir), t = dot(e.b - origin, dir);
      const int sign = s < t ? 1 : -1;
      if (s > t) std::swap(s, t);
      events.push_back({s, sign});
      events.push_back({t, -sign});
    }
    std::sort(events.begin(), events.end());
    int winding = 0;
    double openLength = 0;
    for (size_t i = 0; i + 1 < events.size(); ++i) {
      winding += events[i].second;
      const double span = events[i + 1].first - events[i].first;
      if (winding != 0 && span > tolerance) openLength += span;
    }
    if (openLength > 0) {
      result.isClosed = false;
      result.openEdgeLength += openLength;
      ++result.openEdgeCount;
    }
  }
  return result;
}

}  // namespace

ClosednessReport checkClosedness(const Scene& scene, const PosedScene& posed) {
  ClosednessReport report;
  const double tolerance = 1e-9 * std::max(1.0, posed.extent.diagonalLength());
  std::vector<std::vector<const WorldPolygon*>> byObject(scene.objects.size());
  std::vector<const WorldPolygon*> all, nonEmitting;
  for (const WorldPolygon& p : posed.polygons) {
    byObject[p.objectIndex].push_back(&p);
    all.push_back(&p);
    if (!p.isLight) nonEmitting.push_back(&p);
  }
  for (size_t i = 0; i < byObject.size(); ++i)
    report.objects.push_back(checkChain(int(i), byObject[i], tolerance));
  const ObjectClosedness withoutLights = checkChain(-1, nonEmitting, tolerance);
  report.isSceneClosed = withoutLights.isClosed || checkChain(-1, all, tolerance).isClosed;
  if (!report.isSceneClosed) {
    report.sceneOpenEdgeCount = withoutLights.openEdgeCount;
    report.sceneOpenEdgeLength = withoutLights.openEdgeLength;
  }
  return report;
}

}  // namespace penumbra
