#pragma once
// EEE discontinuity surfaces (Drettakis & Fiume 1994; Teller 1992): the lines meeting three edges
// in general position form a ruled quadric, which meets a receiver in a conic arc.
//   - light edge × two occluder edges e1, e2: where such lines reach a receiver, the crossing of
//     e1's and e2's projections passes over the light edge, and the backprojection gains or loses
//     that crossing vertex;
//   - three occluder edges e1, e2, e3 (only the lines that also meet the light): the crossing of
//     two projected occluder edges passes over the third's projection inside the light, and one
//     crossing vertex of the backprojection is traded for two (or the reverse).
// The arc is traced as a polyline: lines are sampled along the light edge (or along e1), each
// checked for blockers between the light and its farthest contact and followed to the first
// polygon beyond, and the sampling is refined until every chord lies within `chordTolerance` of
// the sampled curve and every change of receiver or visibility is bracketed to that tolerance.
//
// The polyline stands a bounded distance from the true conic; the engine keeps irradiance exact
// by recomputing the backprojection at points within that distance (see DiscontinuityMeshEngine).

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "penumbra/base/first_seen_ids.h"
#include "penumbra/base/key_counts.h"
#include "penumbra/dm/discontinuity_surface.h"
#include "penumbra/dm/edge_adjacency.h"
#include "penumbra/dm/surface_enumeration.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

enum class EeeKind {
  kLightEdge,      // light edge × two occluder edges
  kOccluderEdges,  // three occluder edges, lines meeting the light
};

struct EeeSurface {
  SurfaceId id = 0;
  PolygonId light = 0;
  EeeKind kind = EeeKind::kLightEdge;
  int lightEdge = -1;  // kLightEdge: light edge lightEdge → lightEdge + 1
  EdgeId first = 0, second = 0,
         third = -1;       // occluder edges (EdgeAdjacency); third: kOccluderEdges
  std::vector<int> cells;  // grid cells the traced lines cross (sorted)
  bool truncated = false;  // tracing stopped at its line budget (a degenerate conic)

  // The occluder edges of the surface (two or three).
  std::vector<EdgeId> occluderEdges() const;
};

// On which side of the surface's quadric the point p lies: for the three lines of its edges (the
// light edge's line first), the transversal T(p) through p meeting the first two, oriented from
// the first to the second, against the third line (the sign of their Plücker side product, which
// changes exactly where T(p) meets the third line: on the surface). Scaled to be relative (its
// size compares with 1); NaN where T(p) is not defined (p in a plane with the first line parallel
// to the second). Used where the traced polyline stands within its tolerance of the conic: the
// side decides which face a point belongs to.
double eeeSide(const EeeSurface& surface, const PosedScene& scene, const EdgeAdjacency& adjacency,
               const Vec3& p);
// The sign of eeeSide computed exactly (integer arithmetic on the doubles scaled by one power of
// two) from the doubles of p and the edges' ends: -1, 0 (p on the quadric) or 1; nothing where T(p)
// is not defined. For points where the rounded value is too small to trust (about 1e-11 and below).
std::optional<int> exactEeeSideSign(const EeeSurface& surface, const PosedScene& scene,
                                    const EdgeAdjacency& adjacency, const Vec3& p);

// How many times the straight segment from a to b crosses the surface's quadric (the points
// through which a line meets its three lines), not counting a crossing within rounding of a (where
// a lies on the quadric, or its side is too close to call in doubles): 0, 1 or 2. Along a segment
// the quadric's equation is a polynomial of degree two in the segment's parameter, so three values
// of it give every crossing, also the two of a segment that leaves a side and comes back (where its
// sides at a and b agree). Nothing where rounding could change the count.
std::optional<int> eeeQuadricCrossings(const EeeSurface& surface, const PosedScene& scene,
                                       const EdgeAdjacency& adjacency, const Vec3& a,
                                       const Vec3& b);

// What enumeration found in each EV surface's cuts, kept for the next frame (the paper's
// intersection lists, carried one step further): the candidates a cut polygon's edges form with
// a surface's generator features are a function of those edges, the generators and the light
// alone, so an update takes them over wherever none of these changed.
struct EeeCandidate {
  int lightEdge = -1;           // light-edge surfaces; -1 for three occluder edges
  EdgeId a = 0, b = 0, c = -1;  // the occluder edges (c: the third)
  bool coplanar = false;        // a coplanar pair for coplanarEdgeSurfaces, not a quadric
  bool operator==(const EeeCandidate&) const = default;
};
struct CutCandidates {
  PolygonId polygon = 0;
  std::vector<EeeCandidate> found;  // in the order enumeration meets them
};
struct SurfaceCandidates {
  PolygonId light = -1;
  SurfaceKind kind = SurfaceKind::kEmitterVertexOccluderEdge;
  int lightFeature = 0, occluderFeature = 0, secondFeature = -1;  // the surface's generators
  std::vector<CutCandidates> cuts;                                // by cut polygon, ascending
};
struct EeeCandidateMemo {
  std::vector<SurfaceCandidates> bySurface;  // by EV surface index
  // Three-edge candidates from a light-edge surface's crossed polygon, by (light, first edge,
  // second edge, polygon): each crossing's candidates are `crossingCandidates[begin, end)` of
  // its range, the crossing's id in `crossingIds`. (Flat lists, not a tree: a large room has
  // hundreds of thousands of crossings, each made again every frame.)
  FirstSeenIds<std::array<int, 4>> crossingIds;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> crossingRanges;  // by crossing id
  std::vector<EeeCandidate> crossingCandidates;
  long long keptCuts = 0, foundCuts = 0;  // cuts (and crossings) taken over, and examined
  // Per light, its light-edge candidates (packed keys) counted by the cuts that list them, and
  // the keys counted, ascending: an update counts the candidates of the cuts that changed up or
  // down instead of listing every cut's again (the reference-counted candidates of Loscos &
  // Drettakis), and the surfaces are the keys counted.
  struct Counted {
    KeyCounts counts;
    std::vector<std::uint64_t> keys;
  };
  std::map<PolygonId, Counted> byLight;
};
// The frame before's memo and how to read it now (its per-surface entries are moved out as they
// are taken over: each is taken by one surface at most).
struct EeeCandidateReuse {
  EeeCandidateMemo& before;
  const std::vector<int>& previousIndex;  // per EV surface: its index in the frame before, or -1
  const UnchangedTopology& unchanged;     // polygons, edges and vertices as they were then
};

// Two occluder edges within this fraction of the scene's size of one plane count as coplanar (their
// EEE surfaces are that plane's fans; see inOnePlane in eee_surfaces.cpp).
inline constexpr double kCoplanarEdgeTolerance = 1e-10;

// Surfaces for every light edge and pair of silhouette-capable occluder edges (not sharing a
// vertex) that some line meeting all three crosses in front of the light, in the order of their
// (first edge, second edge, light edge). The pairs come from the emitter EV surfaces of `light`
// after casting: every range of such lines ends on a line of one of their fans, where the other
// edge's polygon cuts it.
// With `coplanar`, the candidate pairs whose two edges are coplanar (their lines meeting the light
// edge lie in one plane: no quadric; within kCoplanarEdgeTolerance) are appended there
// (coplanarEdgeSurfaces builds their fans), in the same order.
std::vector<EeeSurface> enumerateEeeSurfaces(const PosedScene& scene,
                                             const EdgeAdjacency& adjacency,
                                             const std::vector<DiscontinuitySurface>& evSurfaces,
                                             PolygonId light, SurfaceId firstId,
                                             std::vector<CoplanarEdgePair>* coplanar = nullptr,
                                             EeeCandidateMemo* memo = nullptr,
                                             const EeeCandidateReuse* reuse = nullptr);

// Surfaces for every triple of silhouette-capable occluder edges (pairwise sharing no vertex, no
// two coplanar) that some line meeting all three and the light's interior crosses in front of the
// light. Every range of such lines ends on a line through an endpoint of one of the edges, which
// lies in a non-emitter EV fan of `evSurfaces` where the third edge's polygon cuts it, or on a
// line through a light edge, which lies in a light-edge EEE surface whose lines on one side of it
// cross the third edge's polygon: `crossings` holds those (the surface's two occluder edges, a
// polygon its traced lines cross; traceEeeSurface).
struct EeeCrossing {
  EdgeId first = 0, second = 0;
  PolygonId polygon = 0;
};
std::vector<EeeSurface> enumerateOccluderEeeSurfaces(
    const PosedScene& scene, const EdgeAdjacency& adjacency,
    const std::vector<DiscontinuitySurface>& evSurfaces, const std::vector<EeeCrossing>& crossings,
    PolygonId light, SurfaceId firstId, EeeCandidateMemo* memo = nullptr,
    const EeeCandidateReuse* reuse = nullptr);

// The visible pieces of `surface` on receivers, as polylines split into segments (and fills
// surface.cells). With `crossed`, a light-edge surface sets it to the polygons its traced lines
// cross in front of the light, up to their first blocker (for enumerateOccluderEeeSurfaces).
// With `lines`, every critical line the tracing followed, from the light to beyond the scene: the
// result reads only polygons that one of them crosses (and the surface's own edges' polygons), so
// a later frame in which no moved polygon's old or new bounds meet any of them traces the same.
std::vector<DiscontinuitySegment> traceEeeSurface(
    EeeSurface& surface, const PosedScene& scene, const EdgeAdjacency& adjacency,
    const UniformGrid& grid, double chordTolerance, std::vector<PolygonId>* crossed = nullptr,
    std::vector<std::pair<Vec3, Vec3>>* lines = nullptr);

}  // namespace penumbra
