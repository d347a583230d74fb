// Haines & Wallace 1991, "Shaft culling for efficient ray-traced radiosity" (box-to-box shafts).
//
// The hull box is the union of the two boxes. Where a face of the hull is set by one box only and
// an adjacent face (another axis) by the other box only, the hull's edge between those faces lies
// outside the convex hull of the boxes; the plane through the two boxes' corresponding edges
// (parallel to the third axis) cuts that corner off.

#include "penumbra/spatial/shaft.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "penumbra/base/check.h"

namespace penumbra {

namespace {

double coordinate(const Vec3& v, int axis) {
  return axis == 0 ? v.x : axis == 1 ? v.y : v.z;
}
void setCoordinate(Vec3& v, int axis, double value) {
  (axis == 0 ? v.x : axis == 1 ? v.y : v.z) = value;
}
// The corner of `box` furthest along the plane normal n (outwards), or against it (the corner
// furthest towards the inside).
Vec3 cornerAlong(const Box3& box, const Vec3& n, bool outwards) {
  const auto pick = [&](double component, double low, double high) {
    return (component > 0) == outwards ? high : low;
  };
  return {pick(n.x, box.min.x, box.max.x), pick(n.y, box.min.y, box.max.y),
          pick(n.z, box.min.z, box.max.z)};
}
// Extent of `box` on the face (axis, side): side 0 is the min face, 1 the max face.
double faceOf(const Box3& box, int axis, int side) {
  return coordinate(side == 0 ? box.min : box.max, axis);
}

}  // namespace

Shaft::Shaft(const Box3& a, const Box3& b) {
  CHECK(!a.isEmpty() && !b.isEmpty());
  hull_ = a;
  hull_.extend(b);
  // owner[axis][side]: 1 when only `a` reaches that hull face, 2 when only `b`, 0 when both.
  int owner[3][2];
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const double fa = faceOf(a, axis, side), fb = faceOf(b, axis, side);
      owner[axis][side] = fa == fb ? 0 : ((side == 0) == (fa < fb) ? 1 : 2);
    }
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      for (int si = 0; si < 2; ++si)
        for (int sj = 0; sj < 2; ++sj) {
          const int oi = owner[i][si], oj = owner[j][sj];
          if (oi == 0 || oj == 0 || oi == oj) continue;
          // The two boxes' edges at (face i, face j); the plane contains both and the third axis.
          const double pi = faceOf(a, i, si), pj = faceOf(a, j, sj);
          const double qi = faceOf(b, i, si), qj = faceOf(b, j, sj);
          const double di = qi - pi, dj = qj - pj;
          // Perpendicular to (di, dj), oriented towards the hull corner (si, sj) it cuts off.
          double ni = dj, nj = -di;
          const double towardsCorner = ni * (si == 0 ? -1 : 1) + nj * (sj == 0 ? -1 : 1);
          if (towardsCorner < 0) ni = -ni, nj = -nj;
          Vec3 normal{0, 0, 0};
          setCoordinate(normal, i, ni);
          setCoordinate(normal, j, nj);
          if (length(normal) == 0) continue;
          Vec3 point{0, 0, 0};
          setCoordinate(point, i, pi);
          setCoordinate(point, j, pj);
          CHECK_LT(int(planeCount_), kMaxPlanes);
          planes_[planeCount_++] = Plane::fromPointNormal(point, normal);
        }
}

Shaft::Shaft(const Polygon3& a, const Polygon3& b) {
  CHECK(a.size() >= 3 && b.size() >= 3);
  std::vector<Vec3> points(a.begin(), a.end());
  points.insert(points.end(), b.begin(), b.end());
  CHECK_LE(points.size(), 8u);
  Box3 ba, bb;
  for (const Vec3& p : a) ba.extend(p);
  for (const Vec3& p : b) bb.extend(p);
  hull_ = ba;
  hull_.extend(bb);
  // Relative tolerance: a plane supports the hull when no point lies further than this outside.
  const double tolerance = 1e-9 * std::max(1.0, hull_.diagonalLength());
  const auto addSupportingPlane = [&](const Vec3& p, const Vec3& q, const Vec3& r) {
    const Vec3 normal = cross(q - p, r - p);
    if (length(normal) <= 1e-12 * std::max(1.0, dot(q - p, q - p) + dot(r - p, r - p))) return;
    Plane plane = Plane::fromPointNormal(p, normal);
    bool anyAbove = false, anyBelow = false;
    for (const Vec3& x : points) {
      const double d = plane.signedDistance(x);
      anyAbove = anyAbove || d > tolerance;
      anyBelow = anyBelow || d < -tolerance;
    }
    if (anyAbove && anyBelow) return;
    if (!anyAbove && !anyBelow) return;     // every point in the plane: no volume
    if (anyAbove) plane = plane.flipped();  // outward: every point on the inner side
    for (int k = 0; k < planeCount_; ++k)
      if (dot(planes_[k].normal, plane.normal) > 1 - 1e-12 &&
          std::abs(planes_[k].offset - plane.offset) <= tolerance)
        return;  // the same face found through another triple
    // A hull has at most 12 faces; rounding may split a face into near-duplicates beyond that.
    // Dropping a plane only makes the shaft larger, so it stays conservative.
    if (planeCount_ < kMaxPlanes) planes_[planeCount_++] = plane;
  };
  // Every face of the hull of two convex polygons is a polygon's own plane or contains an edge of
  // one polygon and a vertex of the other (or two parallel edges, found the same way).
  for (const Polygon3* pair : {&a, &b}) {
    const Polygon3& edges = *pair;
    const Polygon3& other = pair == &a ? b : a;
    addSupportingPlane(edges[0], edges[1], edges[2]);
    for (size_t i = 0; i < edges.size(); ++i)
      for (const Vec3& v : other) addSupportingPlane(edges[i], edges[(i + 1) % edges.size()], v);
  }
  if (planeCount_ < 4) {  // flat: no convex hull with volume
    *this = Shaft(ba, bb);
    return;
  }
  isPolygonShaft_ = true;
}

bool Shaft::mayIntersect(const Box3& box) const {
  if (!hull_.overlaps(box)) return false;
  for (int k = 0; k < planeCount_; ++k)
    if (planes_[k].signedDistance(cornerAlong(box, planes_[k].normal, false)) > 0) return false;
  return true;
}

bool Shaft::containsBox(const Box3& box) const {
  if (box.isEmpty() || !(hull_.contains(box.min) && hull_.contains(box.max))) return false;
  for (int k = 0; k < planeCount_; ++k)
    if (planes_[k].signedDistance(cornerAlong(box, planes_[k].normal, true)) > 0) return false;
  return true;
}

bool Shaft::contains(const Vec3& p, double tolerance) const {
  if (!hull_.expanded(tolerance).contains(p)) return false;
  for (int k = 0; k < planeCount_; ++k)
    if (planes_[k].signedDistance(p) > tolerance) return false;
  return true;
}

}  // namespace penumbra
