#pragma once
// Stable keys of planar discontinuity surfaces: step 1 of the plan "persistent lists under stable
// keys" (docs/shadows.md, issue 16). A surface is a function of its light, its kind, its
// generators and the polygons in its region; its key names the first three by references a move
// leaves alone — a scene vertex or edge by the lowest polygon incident to it and its corner there
// (EdgeAdjacency numbers vertices and edges afresh every frame), a polygon by its id — plus the
// surface's hinge polygons and an ordinal among the surfaces with all of that in common (the
// several ranges of one generator set, in the order their enumeration makes them: along the
// light's trace, or by the crossing point's key). Its position in the frame's list is not in it.
//
// What the key is for: lists kept from frame to frame by key, where an update makes only the
// surfaces whose keys it adds or removes. What makes that sound is checked by
// `SurfaceKeys.NameTheSameSurfaceAfterAnUpdateAsInAFullBuild` (tests/dm/surface_key_test.cpp):
// keys are unique in a frame, and after updates the surface under each key is, bit for bit, the
// surface a full build at that pose makes under it.

#include <compare>
#include <cstdint>
#include <vector>

#include "penumbra/dm/discontinuity_surface.h"
#include "penumbra/dm/edge_adjacency.h"
#include "penumbra/dm/feature_ref.h"

namespace penumbra {

// A scene vertex by its lowest incident polygon and that polygon's lowest corner at it; an edge by
// its lowest polygon and the corner there where the edge begins (its next corner is the other
// end). The same vertex or edge at two frames has the same reference unless its polygons change
// (a contact made or broken).
FeatureRef vertexRef(const EdgeAdjacency& adjacency, VertexId v);
FeatureRef edgeRef(const EdgeAdjacency& adjacency, EdgeId e);

struct SurfaceKey {
  PolygonId light = 0;
  SurfaceKind kind = SurfaceKind::kEmitterVertexOccluderEdge;
  int lightFeature = -1;  // a light vertex or edge index (its own corners), or -1
  // The surface's occluderFeature (a vertex or an edge, by kind) and its secondFeature (an edge,
  // a polygon as {id, -1}, or none as {-1, -1}).
  FeatureRef occluder{-1, -1}, second{-1, -1};
  // The hinge polygons, sorted, hashed (a collision only joins two groups the ordinal still
  // tells apart).
  std::uint64_t hinge = 0;
  int ordinal = 0;
  auto operator<=>(const SurfaceKey&) const = default;
};

// The keys of a frame's planar surfaces (built on `adjacency`), in the list's order.
std::vector<SurfaceKey> surfaceKeys(const std::vector<DiscontinuitySurface>& surfaces,
                                    const EdgeAdjacency& adjacency);

}  // namespace penumbra
