#pragma once
// Topology of the posed scene for visual events: vertices (identified by exact coordinates), edges
// with their incident polygons, and the exact silhouette predicates the discontinuity surfaces
// need. Only edges that can be silhouettes generate events: an edge between two coplanar polygons
// never does, so a triangulated input yields the same events as its polygons (Drettakis & Fiume
// 1994 §4; Loscos & Drettakis 1997 §3).

#include <array>
#include <vector>

#include "penumbra/geometry/predicates.h"

#include "penumbra/scene/posed_scene.h"

namespace penumbra {

using VertexId = int;
using EdgeId = int;

struct SceneVertex {
  Vec3 position;
  std::vector<EdgeId> edges;
  std::vector<PolygonId> polygons;
};

struct SceneEdge {
  VertexId a = 0, b = 0;  // a < b
  std::vector<PolygonId> polygons;
  // False only when the edge joins exactly two coplanar polygons (a flat interior edge).
  bool canBeSilhouette = true;
};

class EdgeAdjacency {
 public:
  explicit EdgeAdjacency(const PosedScene& scene);

  const std::vector<SceneVertex>& vertices() const { return vertices_; }
  const std::vector<SceneEdge>& edges() const { return edges_; }
  const Vec3& position(VertexId v) const { return vertices_[v].position; }
  // The vertex of each corner of each polygon.
  const std::vector<VertexId>& polygonVertices(PolygonId p) const { return polygonVertices_[p]; }
  size_t polygonCount() const { return polygonVertices_.size(); }
  // The edge joining two vertices, or -1.
  EdgeId edgeBetween(VertexId a, VertexId b) const;
  // Calls f(edge) for each edge of polygon p, in corner order; a corner repeated in a row
  // (welded to one vertex) has no edge to the next and is passed over.
  template <class F>
  void forEachEdgeOf(PolygonId p, F&& f) const {
    const std::vector<VertexId>& corners = polygonVertices_[p];
    for (size_t k = 0; k < corners.size(); ++k) {
      const EdgeId e = edgeBetween(corners[k], corners[(k + 1) % corners.size()]);
      if (e >= 0) f(e);
    }
  }

  // Is edge e a silhouette seen from point x: do its incident polygons lie on one side of the plane
  // through x and e? Exact. True for boundary and non-manifold edges and when x is on that plane's
  // degenerate configurations (conservative: an extra event only refines the mesh).
  bool isSilhouetteFrom(EdgeId e, const Vec3& x) const;
  // Can vertex v generate an event with a plane through it: false only inside a flat region (every
  // edge at v is a flat interior edge). Conservative for now: saddle vertices are kept.
  bool canVertexBeSilhouette(VertexId v) const;

 private:
  // What tells the side of the plane through an edge and a point x on which one of its polygons
  // lies beside it: the polygon's vertex farthest from the edge's line, and whether that vertex
  // lies across the line from the polygon's interior beside the edge (a reflex corner: the
  // opposite side). Neither depends on x: found once per edge and polygon, not at every test.
  struct SideWitness {
    Vec3 vertex;
    bool exists = false;  // false: the polygon is degenerate along the edge (side kZero)
    bool across = false;
  };
  SideWitness sideWitness(PolygonId p, const SceneEdge& e) const;
  // The side of the plane through edge e and point x on which the polygon of `witness` lies
  // beside e (exact orientation of its farthest vertex; kZero when x lies in its plane or it is
  // degenerate).
  static Sign sideOf(const SideWitness& witness, const SceneEdge& e,
                     const std::vector<SceneVertex>& vertices, const Vec3& x);

  const PosedScene& scene_;
  std::vector<SceneVertex> vertices_;
  std::vector<SceneEdge> edges_;
  std::vector<std::vector<VertexId>> polygonVertices_;
  // Per edge joining exactly two polygons, their witnesses in the order of its polygons.
  std::vector<std::array<SideWitness, 2>> witnesses_;
};

// What an update may take over from the frame before: per vertex, edge and polygon of `now`,
// whether the one with the same id in `before` is the same (the same points, incident edges and
// polygons, silhouette capability; a polygon: the same corners, each of them and every edge
// between them the same), so that anything computed from it then holds now.
struct UnchangedTopology {
  std::vector<char> vertices, edges, polygons;
};
UnchangedTopology unchangedTopology(const EdgeAdjacency& before, const EdgeAdjacency& now);

}  // namespace penumbra
