#pragma once
// The exact soft-shadow engine (Loscos & Drettakis 1997, building on Drettakis & Fiume 1994): for
// every light, its discontinuity surfaces are enumerated, cast through the regular grid and
// clipped by visibility in their own planes; the visible pieces become edges of a planar mesh on
// every receiver polygon (with contact lines of touching polygons); every face gets a labelled
// backprojection per light, which gives the exact visible light, hence exact irradiance, at any
// point of the face.
//
// Status: EV surfaces with a feature on the light are built (complete for isolated convex
// occluders); non-emitter EV and EEE surfaces are not yet, so where shadows of several occluders
// interact a face may hold more than one backprojection structure. `isExactEverywhere()` says so.

#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "penumbra/base/rgb.h"
#include "penumbra/dm/backprojection.h"
#include "penumbra/dm/discontinuity_surface.h"
#include "penumbra/dm/edge_adjacency.h"
#include "penumbra/dm/receiver_mesh.h"
#include "penumbra/scene/scene.h"

namespace penumbra {

struct DmStats {
  int lights = 0;
  int surfacesEmitterVertex = 0;  // light vertex × occluder edge
  int surfacesEmitterEdge = 0;    // light edge × occluder vertex
  int surfacesNonEmitter = 0;     // occluder vertex × occluder edge
  int surfacesOccluderPlane = 0;  // light edge × an occluder polygon's plane (degenerate EEE)
  long long storedIntersections = 0;
  long long visibleSegments = 0;
  long long contactSegments = 0;
  long long meshVertices = 0, meshEdges = 0, meshFaces = 0;
  long long backprojectionVertices = 0;  // summed over faces and lights
  long long unlabelledBackprojections = 0;
  size_t gridBytes = 0, surfaceCellBytes = 0, intersectionBytes = 0, meshBytes = 0,
         backprojectionBytes = 0;
  double secondsSurfaces = 0, secondsCasting = 0, secondsVisibility = 0, secondsMeshing = 0,
         secondsBackprojections = 0;
};

class DiscontinuityMeshEngine {
 public:
  // Discontinuity segments are lengthened by this fraction of the scene's size at both ends.
  static constexpr double kSegmentExtension = 1e-9;

  DiscontinuityMeshEngine();
  ~DiscontinuityMeshEngine();

  // Full computation of frame `frame`.
  void build(const Scene& scene, int frame);
  void build(PosedScene posed);

  // Exact direct irradiance at p (normal n) on the receiver polygon p lies on, from the
  // backprojections of p's face. Nothing when p lies on no receiver.
  std::optional<Rgb> irradiance(const Vec3& p, const Vec3& n) const;
  const DmStats& stats() const { return stats_; }
  const PosedScene& posedScene() const { return *posed_; }
  const ReceiverMesh* meshOf(PolygonId receiver) const;
  const std::vector<DiscontinuitySurface>& surfaces() const { return surfaces_; }
  // Irradiance at a face sample point of a receiver, for every face (for images and statistics).
  Rgb faceIrradianceAt(PolygonId receiver, int face, const Vec3& p) const;

 private:
  struct FaceData {
    std::vector<Backprojection> perLight;
  };
  struct ReceiverData {
    ReceiverMesh mesh;
    std::vector<FaceData> faces;
  };

  std::unique_ptr<PosedScene> posed_;
  std::unique_ptr<UniformGrid> grid_;
  std::unique_ptr<ExactReference> reference_;
  std::unique_ptr<EdgeAdjacency> adjacency_;
  std::unique_ptr<BackprojectionBuilder> backprojections_;
  std::vector<DiscontinuitySurface> surfaces_;
  std::map<PolygonId, ReceiverData> receivers_;
  DmStats stats_;
};

}  // namespace penumbra
