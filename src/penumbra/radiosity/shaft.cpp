// Haines & Wallace 1991, "Shaft culling for efficient ray-traced radiosity" (box-to-box shafts).
//
// The hull box is the union of the two boxes. Where a face of the hull is set by one box only and
// an adjacent face (another axis) by the other box only, the hull's edge between those faces lies
// outside the convex hull of the boxes; the plane through the two boxes' corresponding edges
// (parallel to the third axis) cuts that corner off.

#include "penumbra/radiosity/shaft.h"

#include "penumbra/base/check.h"

namespace penumbra {

namespace {

double coordinate(const Vec3& v, int axis) {
  return axis == 0 ? v.x : axis == 1 ? v.y : v.z;
}
void setCoordinate(Vec3& v, int axis, double value) {
  (axis == 0 ? v.x : axis == 1 ? v.y : v.z) = value;
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

bool Shaft::mayIntersect(const Box3& box) const {
  if (!hull_.overlaps(box)) return false;
  for (int k = 0; k < planeCount_; ++k) {
    const Vec3& n = planes_[k].normal;
    // The box corner furthest towards the inside of the plane.
    const Vec3 inner{n.x > 0 ? box.min.x : box.max.x, n.y > 0 ? box.min.y : box.max.y,
                     n.z > 0 ? box.min.z : box.max.z};
    if (planes_[k].signedDistance(inner) > 0) return false;
  }
  return true;
}

bool Shaft::contains(const Vec3& p, double tolerance) const {
  if (!hull_.expanded(tolerance).contains(p)) return false;
  for (int k = 0; k < planeCount_; ++k)
    if (planes_[k].signedDistance(p) > tolerance) return false;
  return true;
}

}  // namespace penumbra
