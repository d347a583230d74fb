#include "penumbra/dm/surface_enumeration.h"

#include <algorithm>

namespace penumbra {

namespace {

bool touchesLight(const std::vector<PolygonId>& polygons, PolygonId light) {
  return std::find(polygons.begin(), polygons.end(), light) != polygons.end();
}

}  // namespace

std::vector<DiscontinuitySurface> enumerateEmitterEvSurfaces(const PosedScene& scene,
                                                             const EdgeAdjacency& adjacency,
                                                             PolygonId light, SurfaceId firstId) {
  std::vector<DiscontinuitySurface> surfaces;
  const WorldPolygon& lightPolygon = scene.polygons[light];
  const Plane& lightPlane = lightPolygon.plane;
  const Polygon3& lv = lightPolygon.vertices;
  const auto isInFront = [&](const Vec3& p) { return lightPlane.signedDistance(p) > 0; };

  // Light vertex × occluder edge. The hinge edge is clipped to the light's front half-space: only
  // lines leaving the light's front carry light.
  for (const SceneEdge& edge : adjacency.edges()) {
    if (!edge.canBeSilhouette || touchesLight(edge.polygons, light)) continue;
    Vec3 a = adjacency.position(edge.a), b = adjacency.position(edge.b);
    const double da = lightPlane.signedDistance(a), db = lightPlane.signedDistance(b);
    if (da <= 0 && db <= 0) continue;
    if (da <= 0) a = a + (b - a) * (da / (da - db));
    if (db <= 0) b = b + (a - b) * (db / (db - da));
    if (a == b) continue;
    const EdgeId edgeId = EdgeId(&edge - adjacency.edges().data());
    for (size_t i = 0; i < lv.size(); ++i) {
      if (!adjacency.isSilhouetteFrom(edgeId, lv[i])) continue;
      DiscontinuitySurface s;
      s.id = firstId + SurfaceId(surfaces.size());
      s.kind = SurfaceKind::kEmitterVertexOccluderEdge;
      s.light = light;
      s.lightFeature = int(i);
      s.occluderFeature = edgeId;
      s.hingePolygons = edge.polygons;
      s.fan = {lv[i], lv[i], a, b};
      surfaces.push_back(std::move(s));
    }
  }

  // Light edge × occluder vertex.
  for (size_t v = 0; v < adjacency.vertices().size(); ++v) {
    const SceneVertex& vertex = adjacency.vertices()[v];
    if (!isInFront(vertex.position) || touchesLight(vertex.polygons, light)) continue;
    if (!adjacency.canVertexBeSilhouette(VertexId(v))) continue;
    for (size_t i = 0; i < lv.size(); ++i) {
      DiscontinuitySurface s;
      s.id = firstId + SurfaceId(surfaces.size());
      s.kind = SurfaceKind::kEmitterEdgeOccluderVertex;
      s.light = light;
      s.lightFeature = int(i);
      s.occluderFeature = VertexId(v);
      s.hingePolygons = vertex.polygons;
      s.fan = {lv[i], lv[(i + 1) % lv.size()], vertex.position, vertex.position};
      surfaces.push_back(std::move(s));
    }
  }
  return surfaces;
}

}  // namespace penumbra
