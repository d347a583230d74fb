#include "penumbra/radiosity/face_contacts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "penumbra/geometry/polygon.h"

namespace penumbra {

namespace {

// Calls pair(a, b, facing) for each pair of polygons in one plane with overlapping bounds, facing
// each other or the same way, a before b. Planes are compared in a canonical orientation (first
// non-zero normal component positive), sorted by offset, so only polygons with nearly equal
// offsets are compared.
template <typename Pair>
void forEachCoplanarPair(const PosedScene& scene, Pair&& pair) {
  const double slack = 1e-9 * std::max(1.0, scene.extent.diagonalLength());
  const auto canonicalOffset = [](const Plane& plane) {
    const Vec3& n = plane.normal;
    const double first = n.x != 0 ? n.x : n.y != 0 ? n.y : n.z;
    return first > 0 ? plane.offset : -plane.offset;
  };
  std::vector<std::pair<double, PolygonId>> order;
  for (const WorldPolygon& p : scene.polygons) order.push_back({canonicalOffset(p.plane), p.id});
  std::sort(order.begin(), order.end());
  for (size_t i = 0; i < order.size(); ++i)
    for (size_t j = i + 1; j < order.size() && order[j].first - order[i].first <= 2 * slack; ++j) {
      const WorldPolygon* a = &scene.polygons[order[i].second];
      const WorldPolygon* b = &scene.polygons[order[j].second];
      const double cosine = dot(a->plane.normal, b->plane.normal);
      const bool facing = cosine <= -1 + 1e-9;
      if (!facing && cosine < 1 - 1e-9) continue;
      if (!a->bounds.expanded(slack).overlaps(b->bounds)) continue;
      bool coplanar = true;
      for (const Vec3& v : b->vertices)
        coplanar = coplanar && std::abs(a->plane.signedDistance(v)) <= slack;
      if (!coplanar) continue;
      if (b->id < a->id) std::swap(a, b);
      pair(*a, *b, facing);
    }
}

// A point strictly inside both polygons of a coplanar pair (their centroids, the point between
// them, the middle of their bounds' overlap: the first inside both), or nothing.
std::optional<Vec3> commonPoint(const WorldPolygon& a, const WorldPolygon& b) {
  const PlaneFrame frame = PlaneFrame::fromPlane(a.plane, a.vertices[0]);
  const auto loop = [&](const WorldPolygon& p) {
    Polygon2 out;
    for (const Vec3& v : p.vertices) out.push_back(frame.toLocal(v));
    return out;
  };
  const Polygon2 loopA = loop(a), loopB = loop(b);
  const double slack = 1e-9 * std::max(diameter(a.vertices), diameter(b.vertices));
  const Vec3 low = componentMax(a.bounds.min, b.bounds.min),
             high = componentMin(a.bounds.max, b.bounds.max);
  const Vec3 ca = centroid(a.vertices), cb = centroid(b.vertices);
  for (const Vec3& q : {cb, ca, (ca + cb) * 0.5, (low + high) * 0.5}) {
    const Vec2 local = frame.toLocal(q);
    if (containsPoint(loopA, local) && containsPoint(loopB, local) &&
        !isNearBoundary(loopA, local, slack) && !isNearBoundary(loopB, local, slack))
      return q;
  }
  return std::nullopt;
}

// Where a ray from `from` along unit `d` meets a polygon: its distance, or nothing. The crossing
// with the polygon's plane is tested against its bounds first (`slack` wide), its outline only
// within them: most polygons a ray passes are rejected there.
std::optional<double> rayMeets(const WorldPolygon& polygon, const Vec3& from, const Vec3& d,
                               double slack) {
  const double along = dot(polygon.plane.normal, d);
  if (along == 0) return std::nullopt;
  const double t = -polygon.plane.signedDistance(from) / along;
  if (!(t > 0)) return std::nullopt;
  const Vec3 x = from + d * t;
  if (!polygon.bounds.expanded(slack).contains(x)) return std::nullopt;
  const PlaneFrame frame = PlaneFrame::fromPlane(polygon.plane, polygon.vertices[0]);
  Polygon2 loop;
  for (const Vec3& v : polygon.vertices) loop.push_back(frame.toLocal(v));
  if (!containsPoint(loop, frame.toLocal(x))) return std::nullopt;
  return t;
}

// Are two polygons back to back in one plane the two sides of a sheet (a two-sided card), not
// two surfaces in face-to-face contact? In contact, the polygon lying on the other is a face of a
// solid (a box on the floor, a book on a shelf, a cushion on a seat): from just in front of one of
// them, a ray meets the solid's other faces from behind. Objects are not always closed on their
// own (a chair's leg is open where it meets the seat: straight up, a ray leaves it), so nine rays
// fan out over each side: a sheet has open space on both, every ray meeting a front face or
// nothing (within their reach). The rays meet only the two polygons' own objects
// (`objectPolygons`): the answer is theirs, and no other object moving by changes it (an update
// relies on a cover changing only where a polygon in contact moved).
bool isSheet(const PosedScene& scene, const std::vector<std::vector<PolygonId>>& objectPolygons,
             const WorldPolygon& a, const WorldPolygon& b) {
  const std::optional<Vec3> q = commonPoint(a, b);
  if (!q) return false;
  const double tolerance = 1e-9 * std::max(1.0, scene.extent.diagonalLength());
  const double step = 1e3 * tolerance;
  // The rays reach four times the smaller polygon's size: a solid lying on it has its sides
  // within that of the fan's slanted rays. Only the polygons within reach are tested, so that the
  // cost is not the objects' size for every pair (a mesh of thousands of two-sided cards).
  const double reach = 4 * std::min(diameter(a.vertices), diameter(b.vertices));
  const Box3 around{*q - Vec3{reach, reach, reach}, *q + Vec3{reach, reach, reach}};
  std::vector<PolygonId> candidates;
  const auto collect = [&](int object) {
    for (PolygonId p : objectPolygons[size_t(object)])
      if (p != a.id && p != b.id && scene.polygons[size_t(p)].bounds.overlaps(around))
        candidates.push_back(p);
  };
  collect(a.objectIndex);
  if (b.objectIndex != a.objectIndex) collect(b.objectIndex);
  bool decided = false;  // some ray saw open space (a front face or nothing) without doubt
  for (const WorldPolygon* side : {&a, &b}) {
    const PlaneFrame frame = PlaneFrame::fromPlane(side->plane, *q);
    const Vec3 n = frame.n, u = frame.u, v = frame.v;
    for (const Vec3& direction : {n, n + u, n - u, n + v, n - v, n * 0.3 + u + v, n * 0.3 + u - v,
                                  n * 0.3 - u + v, n * 0.3 - u - v}) {
      const Vec3 d = normalize(direction), from = *q + n * step;
      // The polygons met first, within the tolerance of one another.
      double nearest = std::numeric_limits<double>::infinity();
      std::vector<std::pair<double, PolygonId>> met;
      for (PolygonId p : candidates) {
        const auto t = rayMeets(scene.polygons[size_t(p)], from, d, tolerance);
        if (t && *t <= reach) {
          met.push_back({*t, p});
          nearest = std::min(nearest, *t);
        }
      }
      bool front = false, back = false;
      for (const auto& [t, p] : met)
        if (t <= nearest + tolerance)
          (dot(scene.polygons[size_t(p)].plane.normal, d) > 0 ? back : front) = true;
      // Two polygons back to back where the ray arrives are the sides of a sheet or two solids
      // pressed together (a stack of books): this ray cannot tell whether it left a solid.
      if (front && back) continue;
      if (back) return false;
      decided = true;
    }
  }
  return decided;
}

}  // namespace

std::vector<std::vector<PolygonId>> coveringPolygons(const PosedScene& scene) {
  std::vector<std::vector<PolygonId>> covering(scene.polygons.size()), objectPolygons;
  for (const WorldPolygon& p : scene.polygons) {
    if (objectPolygons.size() <= size_t(p.objectIndex)) objectPolygons.resize(p.objectIndex + 1);
    objectPolygons[size_t(p.objectIndex)].push_back(p.id);
  }
  forEachCoplanarPair(scene, [&](const WorldPolygon& a, const WorldPolygon& b, bool facing) {
    if (facing) {
      if (isSheet(scene, objectPolygons, a, b)) return;  // both sides exposed
      covering[a.id].push_back(b.id);
      covering[b.id].push_back(a.id);
    } else if (a.isLight && !b.isLight) {
      covering[b.id].push_back(a.id);  // a lamp set into a ceiling: the lamp is what shows
    } else {
      covering[a.id].push_back(b.id);
    }
  });
  return covering;
}

}  // namespace penumbra
