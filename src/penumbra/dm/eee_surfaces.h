#pragma once
// EEE discontinuity surfaces with an edge on the light (Drettakis & Fiume 1994; Teller 1992): the
// lines meeting a light edge and two occluder edges e1, e2 form a ruled quadric; where such lines
// reach a receiver, the crossing of e1's and e2's projections passes over the light edge, and the
// backprojection gains or loses that crossing vertex. The surface meets a receiver in a conic
// arc, traced here as a polyline: lines are sampled along the light edge, each checked for
// blockers between the light and its farther contact and followed to the first polygon beyond,
// and the sampling is refined until every chord lies within `chordTolerance` of the sampled
// curve and every change of receiver or visibility is bracketed to that tolerance.
//
// The polyline stands a bounded distance from the true conic; the engine keeps irradiance exact
// by recomputing the backprojection at points within that distance (see DiscontinuityMeshEngine).

#include <vector>

#include "penumbra/dm/discontinuity_surface.h"
#include "penumbra/dm/edge_adjacency.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

struct EeeSurface {
  SurfaceId id = 0;
  PolygonId light = 0;
  int lightEdge = 0;             // light edge lightEdge → lightEdge + 1
  EdgeId first = 0, second = 0;  // occluder edges (EdgeAdjacency)
  std::vector<int> cells;        // grid cells the traced lines cross (sorted)
  bool truncated = false;        // tracing stopped at its line budget (a degenerate conic)
};

// Surfaces for every light edge and pair of silhouette-capable occluder edges (not sharing a
// vertex) that some line meeting all three crosses in front of the light. The pairs come from the
// emitter EV surfaces of `light` after casting: every range of such lines ends on a line of one of
// their fans, where the other edge's polygon cuts it.
std::vector<EeeSurface> enumerateEeeSurfaces(const PosedScene& scene,
                                             const EdgeAdjacency& adjacency,
                                             const std::vector<DiscontinuitySurface>& evSurfaces,
                                             PolygonId light, SurfaceId firstId);

// The visible pieces of `surface` on receivers, as polylines split into segments (and fills
// surface.cells).
std::vector<DiscontinuitySegment> traceEeeSurface(EeeSurface& surface, const PosedScene& scene,
                                                  const EdgeAdjacency& adjacency,
                                                  const UniformGrid& grid, double chordTolerance);

}  // namespace penumbra
