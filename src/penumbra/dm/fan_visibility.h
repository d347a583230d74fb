#pragma once
// Visibility in the plane of a discontinuity surface (Loscos & Drettakis 1997 §3.3): along each
// critical line L(u) of the fan, the event exists only if nothing lies between the light and the
// hinge (0 < s < 1), and it lands on the first polygon beyond the hinge (s > 1). The stored
// intersections are swept in u: between consecutive breakpoints (segment ends and crossings)
// the depth order is constant, so each interval is decided at its middle.
//
// This first version decides orders in floating point with a relative tolerance on s at the hinge
// (a polygon through the hinge, such as a receiver the occluder rests on, terminates the line
// there). Exact predicates replace it in the complete mesh.
//
// An event lands on the first polygon beyond the hinge, and on each other polygon the line meets
// at that depth (within the same tolerance) from its front side: coincident polygons, such as a
// panel lying flat on the floor, each hold it (DESIGN.md §5: the panel does not hide the floor's
// points under it, which then take their values from the floor's faces).

#include <vector>

#include "penumbra/dm/discontinuity_surface.h"

namespace penumbra {

inline constexpr double kHingeDepthTolerance = 1e-9;

// `polygons`: the scene's, by id (which side of a polygon the critical lines arrive on).
std::vector<DiscontinuitySegment> visibleSegments(const DiscontinuitySurface& surface,
                                                  const std::vector<WorldPolygon>& polygons);

}  // namespace penumbra
