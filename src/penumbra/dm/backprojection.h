#pragma once
// Backprojections (Drettakis & Fiume 1994; Stewart & Ghali 1994): the visible part of a light seen
// from a receiver point, as cycles of *labelled* vertices. A label names the scene features that
// make the vertex — a light vertex; a light edge crossed by the projection of an occluder edge; the
// projection of an occluder vertex; the crossing of two projected occluder edges; or a light or
// occluder edge cut by the receiver's horizon (the plane of the point's tangent plane). The
// labelled cycles are constant inside a face of the complete discontinuity mesh, so evaluating them
// at any point of the face — recomputing each vertex from its features, seen from that point —
// gives the exact visible light there, hence exact irradiance by Lambert's formula.
//
// A backprojection is computed at one point from the exact visible region (polygon booleans) and
// each region vertex is labelled by the features that pass through it. A vertex that cannot be
// labelled unambiguously (degenerate configurations) marks the backprojection unlabelled, and
// evaluation then falls back to computing the visible region at the query point.

#include <optional>
#include <vector>

#include "penumbra/dm/edge_adjacency.h"
#include "penumbra/dm/feature_ref.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

enum class BackprojectionVertexKind {
  kLightVertex,               // light corner `lightFeature`
  kLightEdgeHorizon,          // light edge `lightFeature` cut by the horizon
  kLightEdgeOccluderEdge,     // light edge `lightFeature` crossed by projected edge `first`
  kOccluderVertex,            // projection of vertex `first`
  kOccluderEdgeOccluderEdge,  // crossing of projected edges `first` and `second`
  kOccluderEdgeHorizon,       // projected edge `first` cut by the horizon
};

struct BackprojectionVertex {
  BackprojectionVertexKind kind = BackprojectionVertexKind::kLightVertex;
  int lightFeature = 0;
  FeatureRef first, second;
  bool operator==(const BackprojectionVertex&) const = default;
};

struct Backprojection {
  PolygonId light = 0;
  bool isLabelled = true;  // false: evaluation recomputes the region at the query point
  std::vector<std::vector<BackprojectionVertex>> cycles;  // orientation as the visible rings
};

// Do two labelled backprojections name the same scene features (compared as sets of vertex labels,
// so neither a rotated starting vertex nor a doubled degenerate vertex counts as a change)?
bool sameLabels(const Backprojection& a, const Backprojection& b, const EdgeAdjacency& adjacency);

class BackprojectionBuilder {
 public:
  BackprojectionBuilder(const PosedScene& scene, const ExactReference& reference);

  Backprojection compute(PolygonId light, const Vec3& p, const Vec3& n,
                         std::optional<PolygonId> receiver) const;
  // As compute(), also giving the polygons that entered the visible region's boolean operation
  // (VisibleLight::occluders: every polygon in the cone from p to the light).
  Backprojection compute(PolygonId light, const Vec3& p, const Vec3& n,
                         std::optional<PolygonId> receiver,
                         std::vector<PolygonId>& occluders) const;
  // As compute(), with only `candidates` (distinct ids) as possible occluders
  // (ExactReference::visiblePart): the same labels when every polygon that can hide part of
  // the light from p is a candidate. `occluders` gets the candidates in the cone.
  Backprojection computeAmong(PolygonId light, const Vec3& p, const Vec3& n,
                              std::optional<PolygonId> receiver,
                              const std::vector<PolygonId>& candidates,
                              std::vector<PolygonId>& occluders) const;
  // The visible rings of `backprojection` seen from q (normal n), exact while q stays in the region
  // where the labels hold (a face of the complete mesh).
  std::vector<Polygon3> evaluate(const Backprojection& backprojection, const Vec3& q, const Vec3& n,
                                 std::optional<PolygonId> receiver) const;
  Rgb irradiance(const std::vector<Backprojection>& perLight, const Vec3& q, const Vec3& n,
                 std::optional<PolygonId> receiver) const;

 private:
  // Labels the vertices of the visible region seen from p.
  Backprojection labelRegion(const VisibleLight& visible, const Vec3& p, const Vec3& n) const;

  const PosedScene& scene_;
  const ExactReference& reference_;
};

}  // namespace penumbra
