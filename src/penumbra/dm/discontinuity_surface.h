#pragma once
// Discontinuity surfaces (visual events) of a polygonal light (Drettakis & Fiume 1994; Loscos &
// Drettakis 1997 §3). An EV surface is a planar fan of critical lines L(u), u in [0, 1], each
// through a source point S(u) on the light and a hinge point H(u) on an occluder, one of the two
// fixed:
//   - emitter vertex: S = a light vertex (fixed), H(u) on an occluder edge (also S = the point
//                     where an occluder polygon's plane crosses a light edge, H(u) on one of that
//                     polygon's edges);
//   - emitter edge:   S(u) on a light edge, H = an occluder vertex (fixed);
//   - non-emitter:    H = an occluder vertex (fixed), S(u) on the light's trace in the plane of H
//                     and a second occluder edge E, restricted to the lines that also meet E.
//                     The event lies beyond the farther of H and E: depth h(u) = max(1, s_E(u)).
// L(u) is parameterized as S(u) + s (H(u) − S(u)): s in (0, 1) lies between light and hinge
// (where anything blocks the event), s > 1 beyond the hinge (where the event meets receivers).
// Each surface stores, for the incremental update, the grid cells it crosses and its
// intersections with the scene's polygons before visibility (Loscos & Drettakis §3.3).

#include <vector>

#include "penumbra/base/small_ids.h"
#include "penumbra/scene/posed_scene.h"

namespace penumbra {

using SurfaceId = int;

enum class SurfaceKind {
  kEmitterVertexOccluderEdge,  // EV: light vertex, occluder edge
  kEmitterEdgeOccluderVertex,  // EV: light edge, occluder vertex
  kNonEmitterVertexEdge,       // EV: occluder vertex, occluder edge (lines meeting the light)
  // Degenerate EEE: a light edge and two edges of one occluder polygon whose plane cuts the
  // light. Seen from that plane the polygon is edge-on, and which of its edges bounds the visible
  // light switches there. The critical lines run from the point T where the plane crosses the light
  // edge through an edge of the polygon: a fan with the fixed source T.
  kLightEdgeOccluderPlane,
  // Degenerate EEE of the same plane with an occluder edge instead of the light edge: the lines of
  // the plane through the point X where another occluder's edge crosses it, meeting the light's
  // trace in the plane and passing through the polygon. A fan with the fixed hinge X.
  kOccluderPlaneOccluderEdge,
  // The same plane's lines through one of the polygon's own vertices V, tangent to the polygon
  // there, meeting the light's trace: seen from the plane, the polygon's projection is a segment
  // ending at V's projection, and crossing the plane flips it over. A fan with the fixed hinge V.
  kOccluderPlaneOccluderVertex,
  // Degenerate EEE of a light edge and two coplanar occluder edges of different polygons: the
  // lines meeting both lie in their plane, through the point T where it crosses the light edge;
  // seen from that plane the two edges' projections line up, and which of them bounds the
  // visible light switches. A fan with the fixed source T through the first edge, restricted to
  // the lines that also meet the second (a contact).
  kLightEdgeCoplanarEdges,
  // Degenerate EEE of a light edge, an occluder edge in one plane with it (parallel to it, as
  // axis-aligned scenes have them everywhere) and another occluder's boundary crossing that plane
  // at X: seen from the plane, the edge's projection lies along the light edge, and where X's
  // projection bounds the visible part of it, the event ends. The lines of the plane through X
  // meeting the light edge and the occluder edge: a fan with the fixed hinge X. (The light-vertex
  // and light-edge EV fans of that plane hold only the lines through an end of either edge; with
  // an obstacle between them, the rest of the event was lost.)
  kLightEdgeParallelEdgeCrossing,
  // Degenerate EEE of two coplanar occluder edges of different polygons (parallel ones: the front
  // edges of a desk top and of a drawer below it) and a third occluder edge crossing their plane
  // at X: seen from the plane, the two edges' projections coincide, and where the third edge's
  // projection cuts them, the vertex of the visible light switches from one to the other. The
  // lines of the plane through X meeting the light's trace in the plane and both edges: a fan
  // with the fixed hinge X. (The light edges' fans of that plane, kLightEdgeCoplanarEdges, hold
  // only the lines through the trace's ends.)
  kCoplanarEdgesOccluderCrossing,
};

struct CriticalFan {
  Vec3 source0, source1;  // S(0), S(1): equal when the source is a light vertex
  Vec3 hinge0, hinge1;    // H(0), H(1): equal when the hinge is an occluder vertex
  // Segments in the fan's plane that critical lines may also meet beyond the hinge; the event
  // begins past the farthest of them (non-emitter EV: the second edge; occluder plane: the
  // polygon's edges, the polygon being edge-on in the fan). Empty for the emitter EV fans.
  std::vector<std::pair<Vec3, Vec3>> contacts;

  Vec3 source(double u) const { return source0 + (source1 - source0) * u; }
  Vec3 hinge(double u) const { return hinge0 + (hinge1 - hinge0) * u; }
  Vec3 pointAt(double u, double s) const {
    const Vec3 a = source(u);
    return a + (hinge(u) - a) * s;
  }
  // Unit normal of the fan's plane.
  Vec3 normal() const;
  // The u of the critical line through x (x in the fan's plane), and x's s along it.
  double criticalParameter(const Vec3& x) const;
  double depthParameter(const Vec3& x, double u) const;
  // Where along L(u) the event starts: 1 (the hinge), or beyond it where a contact lies farther
  // from the light.
  double hingeDepth(double u) const;
};

// Where a scene polygon cuts the fan (before visibility): a segment in the fan's plane.
struct SurfaceIntersection {
  PolygonId polygon = 0;
  Vec3 p0, p1;
  // Whether the end is where the polygon's boundary crosses the fan's plane (else the fan's own
  // bound clipped the segment there).
  bool boundaryAt0 = false, boundaryAt1 = false;
};

// The polygons incident to a surface's generators: two to six in all but degenerate scenes, held
// in the surface (a large room makes half a million surfaces every frame).
using HingePolygons = SmallIds<6>;

struct DiscontinuitySurface {
  SurfaceId id = 0;
  SurfaceKind kind = SurfaceKind::kEmitterVertexOccluderEdge;
  PolygonId light = 0;
  int lightFeature = 0;     // light vertex index, or light edge index (edge i: vertices i, i+1)
  int occluderFeature = 0;  // EdgeId or VertexId of EdgeAdjacency
  int secondFeature = -1;   // non-emitter EV: the EdgeId of the second contact
  // Polygons incident to the hinge (and second contact): never block the event.
  HingePolygons hingePolygons;
  CriticalFan fan;
  std::vector<int> cells;                          // grid cells the fan crosses (sorted)
  std::vector<SurfaceIntersection> intersections;  // stored before visibility
};

// A visible piece of a surface on a receiver: an edge of that receiver's discontinuity mesh.
struct DiscontinuitySegment {
  SurfaceId surface = 0;
  PolygonId receiver = 0;
  Vec3 p0, p1;
  double u0 = 0, u1 = 0;  // the critical lines through the endpoints
};

}  // namespace penumbra
