#pragma once
// Shafts: the convex volume swept between two boxes, as their common bounding box cut by planes
// (Haines & Wallace 1991, "Shaft culling for efficient ray-traced radiosity"), or between two
// convex polygons, as the convex hull of their vertices (the same paper's polygon-to-polygon
// shafts: planes through an edge of one polygon and a vertex of the other, plus the polygons'
// own planes where they bound the hull), tighter for element-to-element links. A link keeps the
// shaft between its two ends so that a later move can ask cheaply whether a moving box may change
// the link's visibility (Drettakis & Sillion 1997; Schöffel & Pomi 1999 manage which to keep).

#include <array>
#include <cstdint>

#include "penumbra/geometry/box.h"
#include "penumbra/geometry/plane.h"
#include "penumbra/geometry/polygon.h"

namespace penumbra {

class Shaft {
 public:
  // Box shafts: at most two planes per pair of hull faces on different axes, in practice at most
  // 8. Polygon shafts: the hull of at most 8 points has at most 2 x 8 − 4 = 12 faces.
  static constexpr int kMaxPlanes = 12;

  Shaft() = default;
  // Precondition: both boxes are non-empty. Postcondition: the shaft contains the convex hull of
  // the two boxes (every segment from a point of `a` to a point of `b` lies inside it).
  Shaft(const Box3& a, const Box3& b);
  // Precondition: a and b are convex polygons of 3 or 4 vertices. Postcondition: the shaft
  // contains their convex hull (every segment from a point of `a` to a point of `b`). Where the
  // hull is flat (coplanar polygons) the box shaft of their bounds is built instead.
  Shaft(const Polygon3& a, const Polygon3& b);

  // Conservative: false only when `box` certainly misses the shaft (it lies outside the hull box
  // or entirely on the outer side of one plane).
  bool mayIntersect(const Box3& box) const;
  // Conservative the other way: true only when all of `box` certainly lies in the shaft (inside
  // the hull box and on the inner side of every plane). Then mayIntersect is true for every
  // non-empty box inside `box`: both tests are monotone in the box, rounding included (a rounded
  // product or sum is monotone in each argument, and both evaluate the same dot products).
  bool containsBox(const Box3& box) const;
  // Is p inside the shaft (within `tolerance` of it)?
  bool contains(const Vec3& p, double tolerance = 0) const;

  const Box3& hull() const { return hull_; }
  int planeCount() const { return planeCount_; }
  const Plane& plane(int i) const { return planes_[i]; }  // outward normals
  bool isPolygonShaft() const { return isPolygonShaft_; }

 private:
  Box3 hull_;
  std::array<Plane, kMaxPlanes> planes_{};
  std::uint8_t planeCount_ = 0;
  bool isPolygonShaft_ = false;
};

}  // namespace penumbra
