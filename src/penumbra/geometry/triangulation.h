#pragma once
// Triangulation of simple planar polygons (convex or not) by ear clipping.

#include <array>
#include <vector>

#include "penumbra/geometry/polygon.h"

namespace penumbra {

// Triangles as index triples into `polygon`.
//
// Preconditions: `polygon` is planar and simple (findPolygonDefect() returns nothing); collinear
// vertices (straight angles) and consecutive repeated vertices are allowed.
// Postconditions for such input:
//  - every triangle is counter-clockwise around the polygon's Newell normal (the same front side as
//    the polygon) and has non-zero area;
//  - the triangles tile the polygon: their areas sum to area(polygon) and their interiors are
//    disjoint; triangle edges join polygon vertices only (no Steiner points);
//  - with no repeated vertices there are exactly size - 2 triangles using every vertex.
// A polygon with fewer than 3 vertices or zero area gives no triangles. Input that is not simple
// still terminates and yields triangles with the right orientation, but no tiling is promised.
std::vector<std::array<int, 3>> triangulate(const Polygon3& polygon);

}  // namespace penumbra
