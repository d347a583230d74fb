#pragma once
// Events that belong to a receiver's plane rather than to a discontinuity surface cast through the
// scene, as segments on that receiver:
//   - where a light's plane crosses the receiver: beyond that line the light shows its back and
//     disappears whole (the strip of a wall between the light and the ceiling);
//   - where the receiver's plane cuts the light (a box side under a ceiling lamp), the horizon —
//     the plane's trace T1T2 on the light — clips what a point sees. Its vertices change where a
//     projected occluder edge passes through T1 or T2, i.e. on the lines of the plane from T
//     through the points X where occluder edges pierce the plane (beyond X), and where two
//     projected edges cross on the horizon, i.e. on the lines through two piercing points X1, X2
//     (beyond both, seen from the horizon). Visibility is not checked: an event that is hidden
//     only refines the mesh.

#include <vector>

#include "penumbra/dm/discontinuity_surface.h"
#include "penumbra/dm/edge_adjacency.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

std::vector<DiscontinuitySegment> lightPlaneSegments(const WorldPolygon& receiver,
                                                     const WorldPolygon& light, SurfaceId surface);

std::vector<DiscontinuitySegment> horizonSegments(const EdgeAdjacency& adjacency,
                                                  const UniformGrid& grid,
                                                  const WorldPolygon& receiver,
                                                  const WorldPolygon& light, SurfaceId surface);

}  // namespace penumbra
