#pragma once
// Planar polygons in 3D as vertex loops (counter-clockwise seen from the front, DESIGN.md §4),
// and the constructions the engines need on them. Polygons may be non-convex; they must be simple.

#include <optional>
#include <string>
#include <vector>

#include "penumbra/geometry/box.h"
#include "penumbra/geometry/plane.h"

namespace penumbra {

using Polygon3 = std::vector<Vec3>;
using Polygon2 = std::vector<Vec2>;

// Newell's normal: twice the vector area; robust for non-convex and slightly non-planar loops.
Vec3 newellNormal(const Polygon3& polygon);
double area(const Polygon3& polygon);
inline double triangleArea(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * length(cross(b - a, c - a));
}
// Area centroid (not the vertex average). Precondition: non-zero area.
Vec3 centroid(const Polygon3& polygon);
// Plane through the centroid with the unit Newell normal. Precondition: non-zero area.
Plane supportingPlane(const Polygon3& polygon);
Box3 boundingBox(const Polygon3& polygon);
// Largest distance of a vertex from the supporting plane (0 for a planar polygon).
double planarityDeviation(const Polygon3& polygon);
// Largest distance between two vertices.
double diameter(const Polygon3& polygon);

// Sutherland-Hodgman: the part of `polygon` with plane.signedDistance >= 0. For a non-convex
// polygon the result may contain zero-width bridges along the plane; its area is exact, and
// non-zero winding fill ignores the bridges. Returns an empty loop when nothing is left.
Polygon3 clipByPlane(const Polygon3& polygon, const Plane& plane);
// The same into `out` (not aliasing `polygon`), reusing its storage: for callers clipping many
// polygons in a loop, where allocating each result costs more than clipping.
void clipByPlane(const Polygon3& polygon, const Plane& plane, Polygon3& out);
// One Sutherland-Hodgman step: what the edge a→b adds to the clipped loop (a if it is in front,
// then the crossing if the edge crosses the plane).
void clipEdgeByPlane(const Vec3& a, const Vec3& b, const Plane& plane, Polygon3& out);

// 2D frame of a plane: (u, v, n) right-handed, so a loop that is counter-clockwise around n in 3D
// is counter-clockwise in (u, v).
struct PlaneFrame {
  Vec3 origin, u, v, n;

  static PlaneFrame fromPlane(const Plane& plane, const Vec3& origin);
  Vec2 toLocal(const Vec3& p) const { return {dot(p - origin, u), dot(p - origin, v)}; }
  Vec3 toWorld(const Vec2& q) const { return origin + u * q.x + v * q.y; }
};

double signedArea(const Polygon2& polygon);
// Even-odd containment of a point in a 2D loop; points on the boundary may go either way.
bool containsPoint(const Polygon2& polygon, const Vec2& point);
// Whether the point lies within `tolerance` of the loop's boundary (of one of its edges).
bool isNearBoundary(const Polygon2& polygon, const Vec2& point, double tolerance);

// Why a polygon is unusable, or nothing. Checks: finite coordinates, >= 3 distinct vertices,
// non-zero area, planarity within `relativePlanarityTolerance` x diameter, no self-intersection.
std::optional<std::string> findPolygonDefect(const Polygon3& polygon,
                                             double relativePlanarityTolerance = 1e-6);

// Does the closed segment ab cross the polygon (lying in `plane`) at a point inside it (even-odd)?
// A polygon whose plane passes within `tolerance` of a or of b does not count: the segment starts
// or ends on it (RayCaster::isOccluded's rule). Crossings on the polygon's boundary may go either
// way.
bool segmentCrossesPolygon(const Vec3& a, const Vec3& b, const Polygon3& polygon,
                           const Plane& plane, double tolerance);

// Removes consecutive duplicate vertices (and a closing duplicate of the first).
Polygon3 withoutRepeatedVertices(const Polygon3& polygon);

}  // namespace penumbra
