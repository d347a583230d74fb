#include "penumbra/geometry/polygon.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

#include "penumbra/geometry/predicates.h"

namespace penumbra {

Vec3 newellNormal(const Polygon3& polygon) {
  // Sum relative to the first vertex: same result, far less cancellation for distant polygons.
  Vec3 n;
  if (polygon.size() < 3) return n;
  const Vec3& o = polygon[0];
  for (size_t i = 1; i + 1 < polygon.size(); ++i) n += cross(polygon[i] - o, polygon[i + 1] - o);
  return n;
}

double area(const Polygon3& polygon) {
  return 0.5 * length(newellNormal(polygon));
}

Vec3 centroid(const Polygon3& polygon) {
  const Vec3 n = newellNormal(polygon);
  const double nn = dot(n, n);
  const Vec3& o = polygon[0];
  Vec3 sum;
  for (size_t i = 1; i + 1 < polygon.size(); ++i) {
    const double w = dot(cross(polygon[i] - o, polygon[i + 1] - o), n);  // signed, 2x area x |n|
    sum += (o + polygon[i] + polygon[i + 1]) * (w / 3);
  }
  return sum / nn;
}

Plane supportingPlane(const Polygon3& polygon) {
  return Plane::fromPointNormal(centroid(polygon), newellNormal(polygon));
}

Box3 boundingBox(const Polygon3& polygon) {
  Box3 box;
  for (const Vec3& p : polygon) box.extend(p);
  return box;
}

double planarityDeviation(const Polygon3& polygon) {
  const Plane plane = supportingPlane(polygon);
  double worst = 0;
  for (const Vec3& p : polygon) worst = std::max(worst, std::abs(plane.signedDistance(p)));
  return worst;
}

double diameter(const Polygon3& polygon) {
  double worst = 0;
  for (size_t i = 0; i < polygon.size(); ++i)
    for (size_t j = i + 1; j < polygon.size(); ++j)
      worst = std::max(worst, distance(polygon[i], polygon[j]));
  return worst;
}

Polygon3 clipByPlane(const Polygon3& polygon, const Plane& plane) {
  Polygon3 out;
  clipByPlane(polygon, plane, out);
  return out;
}

void clipByPlane(const Polygon3& polygon, const Plane& plane, Polygon3& out) {
  out.clear();
  const size_t n = polygon.size();
  if (n == 0) return;
  out.reserve(n + 2);
  for (size_t i = 0; i < n; ++i)
    clipEdgeByPlane(polygon[i], polygon[i + 1 == n ? 0 : i + 1], plane, out);
  if (out.size() < 3) out.clear();
}

void clipEdgeByPlane(const Vec3& a, const Vec3& b, const Plane& plane, Polygon3& out) {
  const double da = plane.signedDistance(a);
  const double db = plane.signedDistance(b);
  if (da >= 0) out.push_back(a);
  if ((da >= 0) != (db >= 0)) {
    // Compute the crossing from the lexicographically smaller endpoint, so that the two polygons
    // sharing this edge (traversing it in opposite directions) get bit-identical points: no
    // slivers between the clipped pieces of a closed solid.
    const bool fromA = std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    const Vec3& p0 = fromA ? a : b;
    const Vec3& p1 = fromA ? b : a;
    const double d0 = fromA ? da : db, d1 = fromA ? db : da;
    out.push_back(p0 + (p1 - p0) * (d0 / (d0 - d1)));
  }
}

bool isNearBoundary(const Polygon2& polygon, const Vec2& point, double tolerance) {
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec2 a = polygon[i], ab = polygon[(i + 1) % polygon.size()] - a;
    const double t = std::clamp(dot(point - a, ab) / dot(ab, ab), 0.0, 1.0);
    const Vec2 d = point - (a + ab * t);
    if (dot(d, d) <= tolerance * tolerance) return true;
  }
  return false;
}

PlaneFrame PlaneFrame::fromPlane(const Plane& plane, const Vec3& origin) {
  const Vec3 n = plane.normal;
  // Pick the helper axis least aligned with n for a well-conditioned u.
  const int axis = dominantAxis(n);
  const Vec3 helper = axis == 0 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
  const Vec3 u = normalize(cross(helper, n));
  const Vec3 v = cross(n, u);
  return {origin, u, v, n};
}

double signedArea(const Polygon2& polygon) {
  double twice = 0;
  for (size_t i = 0, n = polygon.size(); i < n; ++i)
    twice += cross(polygon[i], polygon[(i + 1) % n]);
  return twice / 2;
}

bool containsPoint(const Polygon2& polygon, const Vec2& p) {
  bool inside = false;
  for (size_t i = 0, n = polygon.size(), j = n - 1; i < n; j = i++) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x)
      inside = !inside;
  }
  return inside;
}

bool segmentCrossesPolygon(const Vec3& a, const Vec3& b, const Polygon3& polygon,
                           const Plane& plane, double tolerance) {
  const double da = plane.signedDistance(a), db = plane.signedDistance(b);
  if (std::abs(da) <= tolerance || std::abs(db) <= tolerance || (da > 0) == (db > 0)) return false;
  const Vec3 p = a + (b - a) * (da / (da - db));
  // Even-odd in the coordinate plane the polygon's normal is most nearly perpendicular to: the
  // projection keeps the loop simple.
  const Vec3& n = plane.normal;
  const int drop = std::abs(n.x) >= std::abs(n.y) && std::abs(n.x) >= std::abs(n.z) ? 0
                   : std::abs(n.y) >= std::abs(n.z)                                 ? 1
                                                                                    : 2;
  const int u = drop == 0 ? 1 : 0, v = drop == 2 ? 1 : 2;
  const double px = p[u], py = p[v];
  bool inside = false;
  for (size_t i = 0, count = polygon.size(), j = count - 1; i < count; j = i++) {
    const double ax = polygon[i][u], ay = polygon[i][v];
    const double bx = polygon[j][u], by = polygon[j][v];
    if ((ay > py) != (by > py) && px < (bx - ax) * (py - ay) / (by - ay) + ax) inside = !inside;
  }
  return inside;
}

Polygon3 withoutRepeatedVertices(const Polygon3& polygon) {
  Polygon3 out;
  for (const Vec3& p : polygon)
    if (out.empty() || !(out.back() == p)) out.push_back(p);
  while (out.size() > 1 && out.front() == out.back()) out.pop_back();
  return out;
}

namespace {

// Do closed segments ab and cd (in the plane, 2D) share a point? Exact.
bool segmentsIntersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const Sign o1 = orientation2d(a, b, c), o2 = orientation2d(a, b, d);
  const Sign o3 = orientation2d(c, d, a), o4 = orientation2d(c, d, b);
  if (o1 != o2 && o3 != o4 && o1 != Sign::kZero && o2 != Sign::kZero && o3 != Sign::kZero &&
      o4 != Sign::kZero)
    return true;
  auto onSegment = [](const Vec2& p, const Vec2& q, const Vec2& r) {  // r collinear with pq
    return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
           r.y <= std::max(p.y, q.y);
  };
  if (o1 == Sign::kZero && onSegment(a, b, c)) return true;
  if (o2 == Sign::kZero && onSegment(a, b, d)) return true;
  if (o3 == Sign::kZero && onSegment(c, d, a)) return true;
  if (o4 == Sign::kZero && onSegment(c, d, b)) return true;
  return false;
}

std::string describe(const Vec3& p) {
  std::ostringstream out;
  out.precision(17);
  out << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  return out.str();
}

// Do consecutive edges p-shared and shared-q fold back onto each other (collinear, overlapping)?
bool foldsBack(const Vec2& p, const Vec2& shared, const Vec2& q) {
  return orientation2d(p, shared, q) == Sign::kZero && dot(p - shared, q - shared) > 0;
}

// Polygons of more vertices than this are checked for simplicity by a sweep over their edges'
// x-intervals instead of every pair of edges, and their size is their bounding box's diagonal.
constexpr size_t kPairwiseVertices = 1024;

// The simplicity check of findPolygonDefect for a polygon of many vertices: each edge against the
// following one (folding back), and against the edges whose bounding boxes overlap its own, found
// by a sweep over the edges sorted by their least x (exact: the boxes are compared as doubles,
// the candidates tested with exact predicates). Near-linear for the outlines of tessellated
// solids and terrain; still quadratic where most edges overlap in x (a star of long spikes).
std::optional<std::string> largePolygonDefect(const Polygon3& polygon, const Polygon2& flat) {
  const size_t n = flat.size();
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    if (foldsBack(flat[i], flat[j], flat[(j + 1) % n]))
      return "self-overlapping polygon: edges " + std::to_string(std::min(i, j)) + " and " +
             std::to_string(std::max(i, j)) + " fold back at " + describe(polygon[j]);
  }
  struct Extent {
    double minX, maxX, minY, maxY;
    size_t edge;
  };
  std::vector<Extent> edges(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec2 &a = flat[i], &b = flat[(i + 1) % n];
    edges[i] = {std::min(a.x, b.x), std::max(a.x, b.x), std::min(a.y, b.y), std::max(a.y, b.y), i};
  }
  std::sort(edges.begin(), edges.end(), [](const Extent& a, const Extent& b) {
    return a.minX < b.minX || (a.minX == b.minX && a.edge < b.edge);
  });
  std::vector<const Extent*> active;
  for (const Extent& e : edges) {
    std::erase_if(active, [&](const Extent* other) { return other->maxX < e.minX; });
    for (const Extent* other : active) {
      if (other->maxY < e.minY || e.maxY < other->minY) continue;
      const size_t i = std::min(e.edge, other->edge), j = std::max(e.edge, other->edge);
      if (j == i + 1 || (i == 0 && j == n - 1)) continue;  // adjacent: checked above
      if (segmentsIntersect(flat[i], flat[(i + 1) % n], flat[j], flat[(j + 1) % n]))
        return "self-intersecting polygon: edge " + std::to_string(i) + " meets edge " +
               std::to_string(j);
    }
    active.push_back(&e);
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> findPolygonDefect(const Polygon3& input,
                                             double relativePlanarityTolerance) {
  for (const Vec3& p : input)
    if (!p.isFinite()) return "vertex with a NaN or infinite coordinate";
  const Polygon3 polygon = withoutRepeatedVertices(input);
  if (polygon.size() < 3)
    return "fewer than 3 distinct vertices (" + std::to_string(polygon.size()) + ")";
  // The size that scales the tolerances: the diameter, or for a polygon of many vertices (a
  // finely tessellated disc) its bounding box's diagonal (within sqrt(3) of it): the diameter
  // takes a pass over every pair of vertices, 60 s for 100,000 of them.
  const double size = polygon.size() <= kPairwiseVertices ? diameter(polygon)
                                                          : boundingBox(polygon).diagonalLength();
  const double vectorArea = length(newellNormal(polygon)) / 2;
  if (!(vectorArea > 1e-12 * size * size)) return "degenerate polygon: zero area";
  const double deviation = planarityDeviation(polygon);
  if (deviation > relativePlanarityTolerance * size) {
    std::ostringstream out;
    out << "non-planar polygon: a vertex lies " << deviation << " from its plane (tolerance "
        << relativePlanarityTolerance * size << ", " << relativePlanarityTolerance << " x its size "
        << size << ")";
    return out.str();
  }
  // Simplicity: no two non-adjacent edges meet, adjacent edges meet only at their shared vertex.
  const PlaneFrame frame = PlaneFrame::fromPlane(supportingPlane(polygon), polygon[0]);
  Polygon2 flat;
  for (const Vec3& p : polygon) flat.push_back(frame.toLocal(p));
  const size_t n = flat.size();
  if (n > kPairwiseVertices) return largePolygonDefect(polygon, flat);
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
      const Vec2 &a = flat[i], &b = flat[(i + 1) % n], &c = flat[j], &d = flat[(j + 1) % n];
      if (!adjacent) {
        if (segmentsIntersect(a, b, c, d))
          return "self-intersecting polygon: edge " + std::to_string(i) + " meets edge " +
                 std::to_string(j);
      } else {
        // Adjacent edges fold back onto each other only if collinear and overlapping.
        const Vec2& shared = (j == i + 1) ? b : a;
        const Vec2& p = (j == i + 1) ? a : b;
        const Vec2& q = (j == i + 1) ? d : c;
        if (foldsBack(p, shared, q))
          return "self-overlapping polygon: edges " + std::to_string(i) + " and " +
                 std::to_string(j) + " fold back at " + describe(polygon[(j == i + 1) ? j : i]);
      }
    }
  }
  return std::nullopt;
}

}  // namespace penumbra
