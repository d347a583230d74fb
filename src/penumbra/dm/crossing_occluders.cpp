#include "penumbra/dm/crossing_occluders.h"

#include "penumbra/dm/receiver_mesh.h"

namespace penumbra {

CrossingOccluders::CrossingOccluders(const PosedScene& scene, const EdgeAdjacency& adjacency,
                                     const std::vector<DiscontinuitySurface>& surfaces,
                                     const std::vector<EeeSurface>& eeeSurfaces)
    : scene_(scene), adjacency_(adjacency), surfaces_(surfaces), eeeSurfaces_(eeeSurfaces) {}

bool CrossingOccluders::addNamedPolygons(const std::vector<SurfaceId>& surfaces,
                                         std::vector<PolygonId>& out) const {
  const SurfaceId polygons = SurfaceId(scene_.polygons.size());
  for (SurfaceId id : surfaces) {
    if (id >= 0 && id < SurfaceId(surfaces_.size())) {
      // The hinge polygons are those incident to every occluder feature of the event (its edge
      // or vertex, the second contact, the edge-on polygon and its neighbours).
      const DiscontinuitySurface& s = surfaces_[id];
      if (s.id != id) return false;
      out.insert(out.end(), s.hingePolygons.begin(), s.hingePolygons.end());
      continue;
    }
    if (id >= SurfaceId(surfaces_.size()) &&
        id < SurfaceId(surfaces_.size() + eeeSurfaces_.size())) {
      const EeeSurface& s = eeeSurfaces_[id - SurfaceId(surfaces_.size())];
      if (s.id != id) return false;  // numbered otherwise than assumed: no shortcut
      for (EdgeId e : s.occluderEdges()) {
        const std::vector<PolygonId>& incident = adjacency_.edges()[e].polygons;
        out.insert(out.end(), incident.begin(), incident.end());
      }
      continue;
    }
    if (id == ReceiverMesh::kTile) continue;  // a tiling line: no event, names no polygon
    // Below the outline's id the engine numbers contact lines (-2 - p), light planes
    // (-2 - N - light), then horizons (-2 - 2N - light); see discontinuity_mesh_engine.cpp.
    const SurfaceId k = ReceiverMesh::kBoundary - 1 - id;
    const bool isLightPlane = k >= polygons && k < 2 * polygons;
    if (!isLightPlane) return false;
  }
  return true;
}

}  // namespace penumbra
