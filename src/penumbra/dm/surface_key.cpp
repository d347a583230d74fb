#include "penumbra/dm/surface_key.h"

#include <algorithm>
#include <map>

#include "penumbra/base/check.h"
#include "penumbra/base/hash_doubles.h"

namespace penumbra {

namespace {

// Which of a surface's features are vertices, edges and polygons (discontinuity_surface.h and the
// enumerations in surface_enumeration.cpp).
enum class Feature { kNone, kVertex, kEdge, kPolygon };

std::pair<Feature, Feature> featuresOf(SurfaceKind kind) {
  switch (kind) {
    case SurfaceKind::kEmitterVertexOccluderEdge:
      return {Feature::kEdge, Feature::kNone};
    case SurfaceKind::kEmitterEdgeOccluderVertex:
      return {Feature::kVertex, Feature::kNone};
    case SurfaceKind::kNonEmitterVertexEdge:
      return {Feature::kVertex, Feature::kEdge};
    case SurfaceKind::kLightEdgeOccluderPlane:
    case SurfaceKind::kOccluderPlaneOccluderEdge:
    case SurfaceKind::kLightEdgeParallelEdgeCrossing:
      return {Feature::kEdge, Feature::kPolygon};
    case SurfaceKind::kOccluderPlaneOccluderVertex:
      return {Feature::kVertex, Feature::kPolygon};
    case SurfaceKind::kLightEdgeCoplanarEdges:
    case SurfaceKind::kCoplanarEdgesOccluderCrossing:
      return {Feature::kEdge, Feature::kEdge};
  }
  return {Feature::kNone, Feature::kNone};
}

FeatureRef refOf(const EdgeAdjacency& adjacency, Feature feature, int id) {
  switch (feature) {
    case Feature::kNone:
      return {-1, -1};
    case Feature::kVertex:
      return vertexRef(adjacency, VertexId(id));
    case Feature::kEdge:
      return edgeRef(adjacency, EdgeId(id));
    case Feature::kPolygon:
      return {PolygonId(id), -1};
  }
  return {-1, -1};
}

}  // namespace

FeatureRef vertexRef(const EdgeAdjacency& adjacency, VertexId v) {
  const std::vector<PolygonId>& polygons = adjacency.vertices()[size_t(v)].polygons;
  CHECK(!polygons.empty());
  const PolygonId lowest = *std::min_element(polygons.begin(), polygons.end());
  const std::vector<VertexId>& corners = adjacency.polygonVertices(lowest);
  const auto corner = std::find(corners.begin(), corners.end(), v);
  CHECK(corner != corners.end());
  return {lowest, int(corner - corners.begin())};
}

FeatureRef edgeRef(const EdgeAdjacency& adjacency, EdgeId e) {
  const SceneEdge& edge = adjacency.edges()[size_t(e)];
  CHECK(!edge.polygons.empty());
  const PolygonId lowest = *std::min_element(edge.polygons.begin(), edge.polygons.end());
  const std::vector<VertexId>& corners = adjacency.polygonVertices(lowest);
  for (size_t k = 0; k < corners.size(); ++k) {
    const VertexId a = corners[k], b = corners[(k + 1) % corners.size()];
    if ((a == edge.a && b == edge.b) || (a == edge.b && b == edge.a)) return {lowest, int(k)};
  }
  CHECK(false);  // an edge's polygons have it between two consecutive corners
  return {};
}

std::vector<SurfaceKey> surfaceKeys(const std::vector<DiscontinuitySurface>& surfaces,
                                    const EdgeAdjacency& adjacency) {
  std::vector<SurfaceKey> keys;
  keys.reserve(surfaces.size());
  // The next ordinal of each group (the key without it).
  std::map<SurfaceKey, int> next;
  for (const DiscontinuitySurface& s : surfaces) {
    const auto [first, second] = featuresOf(s.kind);
    SurfaceKey key;
    key.light = s.light;
    key.kind = s.kind;
    key.lightFeature = s.lightFeature;
    key.occluder = refOf(adjacency, first, s.occluderFeature);
    key.second = refOf(adjacency, second, s.secondFeature);
    std::vector<int> hinge(s.hingePolygons.begin(), s.hingePolygons.end());
    std::sort(hinge.begin(), hinge.end());
    std::uint64_t h = hinge.size();
    for (int id : hinge) h = hashCombine(h, double(id));
    key.hinge = h;
    key.ordinal = next[key]++;
    keys.push_back(key);
  }
  return keys;
}

}  // namespace penumbra
