#pragma once
// Which polygons can start to hide a light when a point crosses an edge of a receiver's
// discontinuity mesh. Inside a face of a complete mesh the labels of every backprojection are
// constant, and they change only across the events on the face's edges, through the features
// those events name (Drettakis & Fiume 1994 §3; Loscos & Drettakis 1997 §3): a polygon that can
// hide light at a neighbour's sample but not at the face's either was already in the face's cone
// or owns a feature of an event of the edge between them. So the neighbour's visible light can be
// computed from the face's cone polygons plus the polygons named here, instead of searching the
// grid (DmOptions::propagateBackprojections).
//
// Only visual events name what changes. Across the segments no surface makes the engine
// computes from scratch: a contact line (beyond it the point is under the contacting solid, whose
// far faces no event names), a horizon event (a polygon piercing the receiver's plane slides into
// the lit light along the horizon, unnamed), the receiver's outline. A light's plane names
// nothing: crossing it the light vanishes whole, and the face behind it, whose cone is empty,
// lends no candidates (the engine then computes from scratch).

#include <vector>

#include "penumbra/dm/discontinuity_surface.h"
#include "penumbra/dm/edge_adjacency.h"
#include "penumbra/dm/eee_surfaces.h"

namespace penumbra {

class CrossingOccluders {
 public:
  // `surfaces` and `eeeSurfaces` as the engine numbers them: EEE ids follow the EV ids.
  CrossingOccluders(const PosedScene& scene, const EdgeAdjacency& adjacency,
                    const std::vector<DiscontinuitySurface>& surfaces,
                    const std::vector<EeeSurface>& eeeSurfaces);

  // Appends to `out` the polygons owning the features of the events of an edge made by
  // `surfaces`. False when one of them is not a visual event that names what changes: the
  // neighbour must then be computed from scratch (`out` is then unspecified).
  bool addNamedPolygons(const std::vector<SurfaceId>& surfaces, std::vector<PolygonId>& out) const;

 private:
  const PosedScene& scene_;
  const EdgeAdjacency& adjacency_;
  const std::vector<DiscontinuitySurface>& surfaces_;
  const std::vector<EeeSurface>& eeeSurfaces_;
};

}  // namespace penumbra
