#include "penumbra/dm/edge_adjacency.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <utility>
#include <vector>

#include "penumbra/base/first_seen_ids.h"
#include "penumbra/geometry/predicates.h"

namespace penumbra {

namespace {

using CoordinateKey = std::array<std::uint64_t, 3>;

// Exact identity of a point: its bit pattern (+0 and -0 unified).
CoordinateKey keyOf(const Vec3& p) {
  const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v == 0 ? 0.0 : v); };
  return {bits(p.x), bits(p.y), bits(p.z)};
}

bool arePolygonsCoplanar(const Polygon3& p, const Polygon3& q) {
  // Three non-collinear vertices of p span its plane; every vertex of q must lie on it (exact).
  for (size_t i = 2; i < p.size(); ++i) {
    if (squaredLength(cross(p[1] - p[0], p[i] - p[0])) == 0) continue;
    for (const Vec3& w : q)
      if (orientation3d(p[0], p[1], p[i], w) != Sign::kZero) return false;
    return true;
  }
  return false;
}

// The direction, in p's plane and across edge e, towards p's interior beside e: a polygon's
// interior lies left of its edges as its corners run counter-clockwise around its normal.
Vec3 interiorSide(const WorldPolygon& p, const std::vector<VertexId>& corners, const SceneEdge& e) {
  for (size_t k = 0; k < corners.size(); ++k) {
    const VertexId from = corners[k], to = corners[(k + 1) % corners.size()];
    if ((from == e.a && to == e.b) || (from == e.b && to == e.a)) {
      const Vec3 direction = p.vertices[(k + 1) % corners.size()] - p.vertices[k];
      return cross(p.plane.normal, direction);
    }
  }
  return {};
}

}  // namespace

EdgeAdjacency::EdgeAdjacency(const PosedScene& scene) : scene_(scene) {
  std::size_t corners = 0;
  for (const WorldPolygon& polygon : scene.polygons) corners += polygon.vertices.size();
  FirstSeenIds<CoordinateKey> vertexIndex(corners);
  FirstSeenIds<std::array<std::uint32_t, 2>> edgeIndex(corners);
  polygonVertices_.resize(scene.polygons.size());
  vertices_.reserve(corners);
  edges_.reserve(corners);
  for (const WorldPolygon& polygon : scene.polygons) {
    std::vector<VertexId>& ids = polygonVertices_[polygon.id];
    ids.reserve(polygon.vertices.size());
    for (const Vec3& p : polygon.vertices) {
      const auto [id, inserted] = vertexIndex.idOf(keyOf(p), int(vertices_.size()));
      if (inserted) vertices_.push_back({p, {}, {}});
      ids.push_back(VertexId(id));
      std::vector<PolygonId>& at = vertices_[size_t(id)].polygons;
      if (at.empty() || at.back() != polygon.id) at.push_back(polygon.id);
    }
    for (size_t i = 0; i < ids.size(); ++i) {
      VertexId a = ids[i], b = ids[(i + 1) % ids.size()];
      if (a == b) continue;
      if (a > b) std::swap(a, b);
      const auto [id, inserted] =
          edgeIndex.idOf({std::uint32_t(a), std::uint32_t(b)}, int(edges_.size()));
      if (inserted) {
        edges_.push_back({a, b, {}, true});
        vertices_[a].edges.push_back(EdgeId(id));
        vertices_[b].edges.push_back(EdgeId(id));
      }
      edges_[size_t(id)].polygons.push_back(polygon.id);
    }
  }
  for (SceneEdge& e : edges_) {
    if (e.polygons.size() != 2) continue;
    const WorldPolygon& p = scene.polygons[e.polygons[0]];
    const WorldPolygon& q = scene.polygons[e.polygons[1]];
    // Coplanar polygons on either side of the edge make a flat region there; on the same side
    // (coincident copies of one polygon, a double-sided panel's two faces) the edge is a knife
    // edge that light grazes like any outline.
    e.canBeSilhouette = !arePolygonsCoplanar(p.vertices, q.vertices) ||
                        dot(interiorSide(p, polygonVertices_[p.id], e),
                            interiorSide(q, polygonVertices_[q.id], e)) > 0;
  }
  witnesses_.resize(edges_.size());
  for (size_t k = 0; k < edges_.size(); ++k) {
    const SceneEdge& e = edges_[k];
    if (e.polygons.size() == 2 && e.canBeSilhouette)
      witnesses_[k] = {sideWitness(e.polygons[0], e), sideWitness(e.polygons[1], e)};
  }
}

EdgeAdjacency::SideWitness EdgeAdjacency::sideWitness(PolygonId p, const SceneEdge& e) const {
  const Vec3& a = vertices_[e.a].position;
  const Vec3& b = vertices_[e.b].position;
  const WorldPolygon& polygon = scene_.polygons[p];
  // The vertex farthest from the edge's line: its side of the line is the least sensitive to
  // rounding (the first one off the line could lie within rounding of it).
  const Vec3* w = nullptr;
  double farthest = 0;
  for (const Vec3& v : polygon.vertices)
    if (const double d = squaredLength(cross(b - a, v - a)); d > farthest) {
      farthest = d;
      w = &v;
    }
  if (!w) return {};
  // A non-convex polygon has vertices on both sides of an edge's line (a reflex corner): one that
  // lies across the line from the polygon's interior beside the edge tells the opposite side.
  // Measured (dm_geometry fuzzer): a pentagon's far vertex across the edge it shared with a ramp
  // piercing the floor made the edge no silhouette, and the ramp's shadow was lost.
  const double across = dot(interiorSide(polygon, polygonVertices_[p], e), *w - a);
  return {*w, true, across < 0};
}

Sign EdgeAdjacency::sideOf(const SideWitness& witness, const SceneEdge& e,
                           const std::vector<SceneVertex>& vertices, const Vec3& x) {
  if (!witness.exists) return Sign::kZero;
  const Sign side =
      orientation3d(vertices[e.a].position, vertices[e.b].position, x, witness.vertex);
  return witness.across ? Sign(-int(side)) : side;
}

bool EdgeAdjacency::isSilhouetteFrom(EdgeId id, const Vec3& x) const {
  const SceneEdge& e = edges_[id];
  if (!e.canBeSilhouette) return false;
  if (e.polygons.size() != 2) return true;
  const Sign s1 = sideOf(witnesses_[size_t(id)][0], e, vertices_, x);
  const Sign s2 = sideOf(witnesses_[size_t(id)][1], e, vertices_, x);
  // Opposite strict sides: the plane cuts through the dihedral, x sees one face from each side of
  // the edge, so nothing appears or disappears there.
  return !(s1 != Sign::kZero && s2 != Sign::kZero && s1 != s2);
}

EdgeId EdgeAdjacency::edgeBetween(VertexId a, VertexId b) const {
  for (EdgeId e : vertices_[a].edges)
    if ((edges_[e].a == a && edges_[e].b == b) || (edges_[e].a == b && edges_[e].b == a)) return e;
  return -1;
}

bool EdgeAdjacency::canVertexBeSilhouette(VertexId v) const {
  // Inside a flat region every edge at v joins two coplanar polygons; a corner of a flat region
  // (a boundary edge at v) or any fold makes v a feature that light can graze.
  for (EdgeId e : vertices_[v].edges)
    if (edges_[e].canBeSilhouette) return true;
  return false;
}

UnchangedTopology unchangedTopology(const EdgeAdjacency& before, const EdgeAdjacency& now) {
  UnchangedTopology same;
  const auto& edges = now.edges();
  same.edges.assign(edges.size(), 0);
  for (size_t e = 0; e < edges.size() && e < before.edges().size(); ++e) {
    const SceneEdge &a = before.edges()[e], &b = edges[e];
    same.edges[e] = a.a == b.a && a.b == b.b && a.polygons == b.polygons &&
                    a.canBeSilhouette == b.canBeSilhouette &&
                    before.position(a.a) == now.position(b.a) &&
                    before.position(a.b) == now.position(b.b);
  }
  const auto& vertices = now.vertices();
  same.vertices.assign(vertices.size(), 0);
  for (size_t v = 0; v < vertices.size() && v < before.vertices().size(); ++v) {
    const SceneVertex &a = before.vertices()[v], &b = vertices[v];
    same.vertices[v] =
        a.position == b.position && a.edges == b.edges && a.polygons == b.polygons &&
        std::all_of(b.edges.begin(), b.edges.end(), [&](EdgeId e) { return same.edges[e] != 0; });
  }
  const size_t polygons = now.polygonCount();
  same.polygons.assign(polygons, 0);
  for (size_t p = 0; p < polygons && p < before.polygonCount(); ++p) {
    const std::vector<VertexId>& corners = now.polygonVertices(PolygonId(p));
    if (corners != before.polygonVertices(PolygonId(p))) continue;
    bool unchanged = std::all_of(corners.begin(), corners.end(),
                                 [&](VertexId v) { return same.vertices[v] != 0; });
    now.forEachEdgeOf(PolygonId(p), [&](EdgeId e) { unchanged = unchanged && same.edges[e] != 0; });
    same.polygons[p] = unchanged;
  }
  return same;
}

}  // namespace penumbra
