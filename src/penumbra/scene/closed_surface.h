#pragma once
// The closed surfaces among polygons: sets of polygons, joined by shared edges, in which every
// edge, taken in the direction its polygon runs, is run once the other way by another polygon of
// the set, its corners equal bit for bit, and by no other polygon at all. (A piece of furniture
// modelled as boxes is one closed surface per box.)
//
// Why it matters: the oriented boundary of such a surface is zero, so it has a winding number
// everywhere off it, 0 outside its bounds, and a segment whose ends both have winding 0 crosses
// it as often from the front of its polygons to their back as from the back to the front. A
// segment from p that meets any of its polygons therefore meets one that faces p (p in front of
// its plane) and one that faces away: the polygons facing p hide from p all that the surface
// hides, wherever the segment's far end lies outside its bounds too (exact_reference.h).
//
// Unlike closedness.h, which allows T-junctions and gaps within a tolerance (whether a scene
// bounds a volume), this is exact: a T-junction or a gap of one ulp leaves a surface open. Edges
// of zero length (a repeated corner) are passed over: they bound nothing.

#include <vector>

#include "penumbra/geometry/polygon.h"

namespace penumbra {

// For each polygon (a ring of corners: consecutive corners and the last and first joined by
// edges), the closed surface it belongs to, numbered 0, 1, ... in the order of their first
// polygons; -1 for a polygon whose connected set of polygons is not closed.
std::vector<int> closedSurfaces(const std::vector<const Polygon3*>& polygons);

}  // namespace penumbra
