#pragma once
// Enumerates the EV discontinuity surfaces of one light (Drettakis & Fiume 1994 §3): light vertex ×
// occluder edge, and light edge × occluder vertex, keeping only occluder features that can be
// silhouettes from the light feature (exact predicates, conservative) and lie in front of the
// light; and non-emitter EV (occluder vertex × occluder edge) restricted to the critical lines that
// meet the light. EEE surfaces are enumerated in eee_surfaces.h.

#include <vector>

#include "penumbra/dm/discontinuity_surface.h"
#include "penumbra/dm/edge_adjacency.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

// The EV surfaces of `light`'s vertices and edges with the occluders' edges and vertices,
// appended to `surfaces` and numbered on from its size (appended in place: a large room's half
// a million are made every frame).
void enumerateEmitterEvSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                                PolygonId light, std::vector<DiscontinuitySurface>& surfaces);

// What an enumeration found per item (a vertex of the non-emitter EV fans, a polygon whose
// plane gives occluder-plane crossings), kept for the next frame: by item id, the polygons of the
// item's region (ascending) whose edges, first examined there, gave surfaces, with those surfaces
// (ids unset). An item's surfaces are a function of the item, the light and the polygons listed
// in the grid cells of its region.
struct FoundByItem {
  std::vector<std::vector<std::pair<PolygonId, std::vector<DiscontinuitySurface>>>> byItem;
  long long kept = 0, examined = 0;  // items taken over, and examined
};
// How to read the frame before's memo, offered when every polygon that did not move kept its
// ids, corners and edges and shares no edge with a moved one: an item flagged in
// `unchangedItems` keeps what the unmoved polygons gave it, and the moved polygons
// (`movedPolygons`, ascending) listed in its region's cells are examined again.
struct FoundByItemReuse {
  FoundByItem& before;  // taken over: what it keeps is moved out
  const std::vector<char>& unchangedItems;
  const std::vector<PolygonId>& movedPolygons;
};
using NonEmitterEvMemo = FoundByItem;  // by vertex id
using NonEmitterEvReuse = FoundByItemReuse;
using OccluderPlaneMemo = FoundByItem;  // by polygon id
using OccluderPlaneReuse = FoundByItemReuse;

// Occluder vertex V × occluder edge E (V not on E), both in front of the light, E a silhouette
// seen from V: the lines through V and E that meet the light, one surface per connected range of
// them. Candidate edges come from the grid cells around the shaft from the light through V.
// Appended to the caller's list `surfaces`, whose k-th surface is numbered firstId + k (as are
// the surfaces of every enumeration below): no list of their own made and moved over every frame
// (a large room's run to tens of thousands).
void enumerateNonEmitterEvSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                                   const UniformGrid& grid, PolygonId light, SurfaceId firstId,
                                   std::vector<DiscontinuitySurface>& surfaces,
                                   NonEmitterEvMemo* memo = nullptr,
                                   const NonEmitterEvReuse* reuse = nullptr);

// For every occluder polygon whose plane cuts the light (light vertices strictly on both sides):
// from each point T where the plane crosses a light edge, one fan through each edge of the polygon
// (see SurfaceKind::kLightEdgeOccluderPlane); and for every other occluder edge crossing that
// plane at X, the lines of the plane through X that meet the light and pass through the polygon
// (SurfaceKind::kOccluderPlaneOccluderEdge); and for each of the polygon's own vertices V, the
// lines of the plane through V tangent to the polygon that meet the light
// (SurfaceKind::kOccluderPlaneOccluderVertex).
void enumerateOccluderPlaneSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                                    const UniformGrid& grid, PolygonId light, SurfaceId firstId,
                                    std::vector<DiscontinuitySurface>& surfaces,
                                    OccluderPlaneMemo* memo = nullptr,
                                    const OccluderPlaneReuse* reuse = nullptr);

// A light edge and two coplanar occluder edges (EdgeAdjacency ids) that some line meets.
struct CoplanarEdgePair {
  int lightEdge = 0;
  EdgeId first = 0, second = 0;
};

// For each pair whose plane crosses the light edge at T (its ends strictly on both sides), the
// fan from T through the first edge restricted to the lines that also meet the second
// (SurfaceKind::kLightEdgeCoplanarEdges); the pairs come from the EEE enumeration, which finds
// them where it finds the light-edge EEE surfaces (enumerateEeeSurfaces).
void coplanarEdgeSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                          const std::vector<CoplanarEdgePair>& pairs, PolygonId light,
                          SurfaceId firstId, std::vector<DiscontinuitySurface>& surfaces);

// The surfaces one polygon gave an item in one frame: that frame's ids first, first + 1, ...
// (their indices among its surfaces).
struct SurfaceRun {
  PolygonId polygon = 0;
  SurfaceId first = 0;
  int count = 0;
};

// What the coplanar-edge crossing enumeration found for each pair of edges, kept for the next
// frame: by pair (ascending), the polygons listed in the pair's region whose edges, first
// examined there, gave surfaces, with those surfaces' ids. A pair's surfaces are a function of
// its two edges, the light and the polygons listed in the grid cells of its region.
struct CoplanarCrossingMemo {
  struct Pair {
    EdgeId first = 0, second = 0;
    std::vector<SurfaceRun> entries;  // by polygon
    Box3 region;                      // where its crossings can lie (a function of its edges)
  };
  std::vector<Pair> pairs;
  long long keptPairs = 0, examinedPairs = 0;
};
// How to read the frame before's memo, offered on the same terms as NonEmitterEvReuse: a pair
// whose two edges are flagged in `unchangedEdges` takes over whole (casts included) the surfaces
// the unmoved polygons gave it, and the moved polygons (`movedPolygons`, ascending) listed in its
// region's cells are examined again.
struct CoplanarCrossingReuse {
  const CoplanarCrossingMemo& before;
  const std::vector<char>& unchangedEdges;
  const std::vector<PolygonId>& movedPolygons;
  std::vector<DiscontinuitySurface>& surfacesBefore;  // the frame before's: those taken moved out
  std::vector<int>& takenFrom;  // per surface returned: its index in the frame before, else -1
};

// For each pair's plane (each pair once, whatever its light edge) that cuts the light, and every
// other occluder edge crossing that plane at X, the lines of the plane through X that meet the
// light's trace in the plane and both edges (SurfaceKind::kCoplanarEdgesOccluderCrossing).
// Candidate edges come from the grid cells around the shaft from the light through the pair.
void coplanarEdgeCrossingSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                                  const UniformGrid& grid,
                                  const std::vector<CoplanarEdgePair>& pairs, PolygonId light,
                                  SurfaceId firstId, std::vector<DiscontinuitySurface>& surfaces,
                                  CoplanarCrossingMemo* memo = nullptr,
                                  const CoplanarCrossingReuse* reuse = nullptr);

// For every light-vertex EV fan (cast: its stored intersections filled) whose occluder edge lies
// in one plane with a light edge at that vertex, and every point X where another polygon's
// boundary crosses that plane (the ends of the fan's stored intersections), the lines of the plane
// through X meeting the light edge and the occluder edge (SurfaceKind::
// kLightEdgeParallelEdgeCrossing).
// (The fans of one such plane are the light-vertex fans of its occluder edge at its light edge's
// two vertices.)
//
// What it made from each plane, kept for the next frame. A plane's surfaces are a function of the
// light, the light edge, the occluder edge (its ends and polygons) and its fans' cuts, in order.
struct ParallelCrossingMemo {
  struct Plane {
    int lightEdge = 0;
    Vec3 a, b;                        // the occluder edge's ends
    std::vector<PolygonId> polygons;  // and polygons
    std::vector<size_t> fans;         // the fans' indices among that frame's surfaces, in order
    SurfaceId first = 0;              // the ids of the plane's surfaces in that frame: first,
    int count = 0;                    // first + 1, ... (their indices among its surfaces)
  };
  std::vector<Plane> planes;
  std::vector<std::pair<size_t, size_t>> byFirstFan;  // (a plane's first fan, the plane), sorted
  long long keptPlanes = 0, examinedPlanes = 0;
};
// How to read the frame before's memo, offered when no light moved: a plane whose fans are, in
// order, fans of the frame before with the same cuts bit for bit, the fans of one plane of the
// memo with the same light edge and occluder edge, takes that plane's surfaces over whole (their
// casts included: they are the frame before's surfaces, renumbered).
struct ParallelCrossingReuse {
  const ParallelCrossingMemo& before;
  // Per surface of this frame (an index into evSurfaces): the index in the frame before of the
  // surface with the same fan whose cuts it has, bit for bit; else -1.
  const std::vector<int>& sameCutsAs;
  std::vector<DiscontinuitySurface>& surfacesBefore;  // the frame before's: those taken moved out
  std::vector<int>& takenFrom;  // per surface returned: its index in the frame before, else -1
};

void parallelEdgeCrossingSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                                  const std::vector<DiscontinuitySurface>& evSurfaces,
                                  PolygonId light, SurfaceId firstId,
                                  std::vector<DiscontinuitySurface>& surfaces,
                                  ParallelCrossingMemo* memo = nullptr,
                                  const ParallelCrossingReuse* reuse = nullptr);

}  // namespace penumbra
