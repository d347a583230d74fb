#include "penumbra/dm/receiver_plane_events.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <tuple>
#include <unordered_set>

namespace penumbra {

namespace {

// The pieces of the line o + t d (in the receiver's plane) inside the receiver polygon, as ranges
// of t: crossings of the polygon's boundary paired along the line (the polygon may be concave).
std::vector<std::array<double, 2>> insideRanges(const WorldPolygon& receiver, const Vec3& o,
                                                const Vec3& d) {
  const Vec3 m = cross(d, receiver.plane.normal);  // normal of the plane through the line
  const Polygon3& v = receiver.vertices;
  const double dd = dot(d, d);
  std::vector<double> ts;
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec3& a = v[i];
    const Vec3& b = v[(i + 1) % v.size()];
    const double da = dot(m, a - o), db = dot(m, b - o);
    if ((da > 0) == (db > 0)) continue;  // half-open: a vertex on the line counts once
    const Vec3 x = a + (b - a) * (da / (da - db));
    ts.push_back(dot(x - o, d) / dd);
  }
  std::sort(ts.begin(), ts.end());
  std::vector<std::array<double, 2>> out;
  for (size_t i = 0; i + 1 < ts.size(); i += 2)
    if (ts[i] < ts[i + 1]) out.push_back({ts[i], ts[i + 1]});
  return out;
}

// The part of the line o + t d inside the receiver with t >= from, as segments.
void addBeyond(std::vector<DiscontinuitySegment>& out, const WorldPolygon& receiver,
               SurfaceId surface, const Vec3& o, const Vec3& d, double from) {
  for (const auto& [t0, t1] : insideRanges(receiver, o, d)) {
    const double a = std::max(t0, from);
    if (a >= t1) continue;
    out.push_back({surface, receiver.id, o + d * a, o + d * t1, 0, 0});
  }
}

}  // namespace

std::vector<DiscontinuitySegment> lightPlaneSegments(const WorldPolygon& receiver,
                                                     const WorldPolygon& light, SurfaceId surface) {
  std::vector<DiscontinuitySegment> out;
  const Vec3 n = receiver.plane.normal, l = light.plane.normal;
  const Vec3 along = cross(n, l);
  if (squaredLength(along) == 0) return out;  // parallel planes
  // The point of both planes n . x = dn and l . x = dl nearest the origin:
  // x = (dn (l × u) + dl (u × n)) / |u|² with u = n × l (it satisfies both: n · (l × u) = |u|²,
  // n · (u × n) = 0, and likewise for l).
  const double dn = receiver.plane.offset, dl = light.plane.offset;
  const Vec3 o = (cross(l, along) * dn + cross(along, n) * dl) / squaredLength(along);
  addBeyond(out, receiver, surface, o, along, -INFINITY);
  return out;
}

std::vector<DiscontinuitySegment> horizonSegments(const EdgeAdjacency& adjacency,
                                                  const UniformGrid& grid,
                                                  const WorldPolygon& receiver,
                                                  const WorldPolygon& light, SurfaceId surface) {
  std::vector<DiscontinuitySegment> out;
  // The horizon: the receiver plane's trace on the light (its extreme crossings).
  std::vector<Vec3> trace;
  const Polygon3& lv = light.vertices;
  for (size_t i = 0; i < lv.size(); ++i) {
    const double da = receiver.plane.signedDistance(lv[i]);
    const double db = receiver.plane.signedDistance(lv[(i + 1) % lv.size()]);
    if ((da > 0) == (db > 0)) continue;
    trace.push_back(lv[i] + (lv[(i + 1) % lv.size()] - lv[i]) * (da / (da - db)));
  }
  if (trace.size() < 2) return out;
  const Vec3 along = trace[1] - trace[0];
  std::sort(trace.begin(), trace.end(),
            [&](const Vec3& a, const Vec3& b) { return dot(a, along) < dot(b, along); });
  const Vec3 t1 = trace.front(), t2 = trace.back();
  if (t1 == t2) return out;

  // Piercing points of silhouette-capable occluder edges between the receiver and the horizon.
  Box3 region = receiver.bounds;
  region.extend(t1);
  region.extend(t2);
  std::vector<Vec3> piercings;
  std::unordered_set<EdgeId> seen;
  for (PolygonId id : grid.polygonsInBox(region)) {
    if (id == receiver.id || id == light.id) continue;
    const std::vector<VertexId>& corners = adjacency.polygonVertices(id);
    for (size_t k = 0; k < corners.size(); ++k) {
      const EdgeId e = adjacency.edgeBetween(corners[k], corners[(k + 1) % corners.size()]);
      if (!seen.insert(e).second) continue;
      const SceneEdge& edge = adjacency.edges()[e];
      if (!edge.canBeSilhouette) continue;
      const Vec3 a = adjacency.position(edge.a), b = adjacency.position(edge.b);
      const double da = receiver.plane.signedDistance(a), db = receiver.plane.signedDistance(b);
      // An endpoint on the plane pierces it too (an edge lying in the plane, like a book's edge
      // on a shelf's side, turns about its endpoints as seen from the plane).
      std::vector<Vec3> here;
      if (da == 0) here.push_back(a);
      if (db == 0) here.push_back(b);
      if ((da > 0 && db < 0) || (da < 0 && db > 0)) here.push_back(a + (b - a) * (da / (da - db)));
      for (const Vec3& x : here)
        if (light.plane.signedDistance(x) > 0 && region.contains(x)) piercings.push_back(x);
    }
  }
  std::sort(piercings.begin(), piercings.end(), [](const Vec3& p, const Vec3& q) {
    return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
  });
  piercings.erase(std::unique(piercings.begin(), piercings.end()), piercings.end());
  // Lines from a horizon end through a piercing point, beyond it.
  for (const Vec3& t : {t1, t2})
    for (const Vec3& x : piercings)
      if (!(x == t)) addBeyond(out, receiver, surface, t, x - t, 1);
  // Lines through two piercing points that meet the horizon between its ends, beyond both.
  const Vec3 h = t2 - t1;
  const Vec3& n = receiver.plane.normal;
  for (size_t i = 0; i < piercings.size(); ++i)
    for (size_t j = i + 1; j < piercings.size(); ++j) {
      const Vec3 d = piercings[j] - piercings[i];
      // Y = t1 + s h on the line x_i + u d: solve in the plane (2D cross products along n).
      const double denominator = dot(n, cross(h, d));
      if (denominator == 0) continue;
      const double s = dot(n, cross(piercings[i] - t1, d)) / denominator;
      if (s < 0 || s > 1) continue;
      const Vec3 y = t1 + h * s;
      const double ui = dot(piercings[i] - y, d), uj = dot(piercings[j] - y, d);
      if ((ui > 0) != (uj > 0) || ui == 0 || uj == 0) continue;  // Y between them: no event
      const Vec3 away = ui > 0 ? d : d * -1.0;
      const double farther = std::max(std::abs(ui), std::abs(uj)) / dot(d, d);
      addBeyond(out, receiver, surface, y, away, farther);
    }
  return out;
}

}  // namespace penumbra
