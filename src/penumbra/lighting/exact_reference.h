#pragma once
// The exact reference of DESIGN.md §5: for a receiver point p with unit normal n, the part of each
// light visible from p is computed by brute force — the light clipped to p's front half-space,
// minus the central projection from p onto the light's plane of every other polygon that lies
// between p and the light — and its irradiance by Lambert's formula over the visible region's
// rings (outer boundaries and holes). Slow, simple, and independent of the engines: the oracle.
//
// Polygon booleans are Clipper's (Vatti's algorithm, 64-bit integer coordinates): the light's 2D
// frame is scaled so that its extent maps to about 2^60, far finer than the doubles that feed it.

#include <optional>
#include <span>
#include <vector>

#include "penumbra/base/rgb.h"
#include "penumbra/scene/posed_scene.h"

namespace penumbra {

class UniformGrid;

// The visible part of one light from a point, as rings on the light's plane: outer rings
// counter-clockwise around the light's normal, holes clockwise.
struct VisibleLight {
  PolygonId light = 0;
  std::vector<Polygon3> rings;
  // The polygons whose projection entered the boolean operation (inside the cone from the point
  // to the lit light), in visiting order: the only ones whose features can bound the rings.
  std::vector<PolygonId> occluders;
};

// Which polygons of a closed object enter the boolean operation (ExactReference's constructor).
enum class ClosedObjectFaces {
  kAll,  // every polygon, as the oracle does
  // Where p and the lit light lie outside the bounds of a closed surface (a box of a piece of
  // furniture: WorldPolygon::closedSurface), only its polygons that face p: they hide all that
  // it hides (closed_surface.h), and they are about half of it. The engines' choice.
  kFacingThePoint,
};

class ExactReference {
 public:
  // `grid` (optional, must outlive this) narrows the occluders considered for a point to those in
  // the cells overlapping the bounding box of the point and the light; without it every polygon is
  // tested. Both give the same answer.
  explicit ExactReference(const PosedScene& scene, const UniformGrid* grid = nullptr,
                          ClosedObjectFaces closedObjectFaces = ClosedObjectFaces::kAll);
  ExactReference(PosedScene&&, const UniformGrid* = nullptr,
                 ClosedObjectFaces = ClosedObjectFaces::kAll) = delete;  // keeps a reference

  // Direct irradiance E(p) = Σ_lights M · F(p, V_light(p)) (W/m² per channel). `receiver`, when
  // given, is the polygon p lies on: it never occludes, even when rounding puts p a little behind
  // it (other polygons whose plane passes through p are skipped in any case).
  Rgb irradiance(const Vec3& p, const Vec3& n, std::optional<PolygonId> receiver = {}) const;
  // The exact visible part of `light` from p (empty rings when nothing is visible).
  VisibleLight visibleLight(const Vec3& p, const Vec3& n, PolygonId light,
                            std::optional<PolygonId> receiver = {}) const;
  // The visible part from p of any convex polygon `source` lying in `sourcePlane` (emitting
  // towards its normal), part of the scene polygon `sourcePolygon` (which never occludes), with
  // only `candidates` considered as occluders: the caller has culled the others (a shaft between
  // a receiver and the source). Used by the radiosity solver for exact link visibility.
  VisibleLight visiblePart(const Vec3& p, const Vec3& n, const Polygon3& source,
                           const Plane& sourcePlane, PolygonId sourcePolygon,
                           std::span<const PolygonId> candidates,
                           std::optional<PolygonId> receiver = {}) const;
  // Lambert's form factor from p (normal n) to that visible part.
  double visibleFormFactor(const Vec3& p, const Vec3& n, const Polygon3& source,
                           const Plane& sourcePlane, PolygonId sourcePolygon,
                           std::span<const PolygonId> candidates,
                           std::optional<PolygonId> receiver = {}) const;
  // Unoccluded form factor of the whole light (clipped to p's front half-space).
  double unoccludedFormFactor(const Vec3& p, const Vec3& n, PolygonId light) const;
  // May a polygon lying inside one of `boxes` enter the boolean operation of
  // visibleLight(p, n, light)? False guarantees that no polygon inside any of them is even
  // considered there, so moving such a polygon within boxes for which this is false leaves
  // visibleLight's result unchanged bit for bit (what the discontinuity mesh's update relies on to
  // keep a face's backprojections). The cone is built once for all the boxes.
  bool mayOcclude(const Vec3& p, const Vec3& n, PolygonId light, std::span<const Box3> boxes) const;
  // The box every cone of visibleLight(·, ·, light) ends in: the light's bounds enlarged as each
  // cone's hull of the lit light is (by its margin about the hull's centre). A polygon's piece
  // inside the cone from p lies in the convex hull of p and this box.
  Box3 coneBaseBounds(PolygonId light) const;

 private:
  // The clipping cone from p to the part of a light in front of p (nothing when no part is):
  // the lit light, its frame, the cone's planes (its sides through the enlarged hull, then the
  // light's plane) and the bounds of the lit light and p.
  struct Cone {
    double pointHeight = 0;
    Polygon3 lit;
    PlaneFrame frame;
    Polygon2 lit2;
    double extent = 0;
    Vec2 hullCenter2;
    std::vector<Plane> planes;
    Box3 bounds;
  };
  std::optional<Cone> coneOf(const Vec3& p, const Vec3& n, const Polygon3& source,
                             const Plane& lightPlane) const;
  // Calls visit(polygon) once for every polygon that may lie in the shaft (bounds overlap
  // `shaftBounds` and are not entirely outside one of `shaftPlanes`).
  template <typename Visit>
  void forEachCandidateOccluder(const Box3& shaftBounds, const std::vector<Plane>& shaftPlanes,
                                Visit&& visit) const;

  // The polygon `source` in `lightPlane` minus the projections from p of the occluders that
  // forEachCandidate(shaftBounds, shaftPlanes, visit) offers.
  template <typename ForEachCandidate>
  VisibleLight visibleRegion(const Vec3& p, const Vec3& n, const Polygon3& source,
                             const Plane& lightPlane, PolygonId lightId,
                             std::optional<PolygonId> receiver,
                             ForEachCandidate&& forEachCandidate) const;

  // With ClosedObjectFaces::kFacingThePoint: does polygon q of a closed surface face away from p
  // (`distance`: p's signed distance to q's plane), with p and the lit light (bounds `lit`)
  // outside the surface's bounds and no polygon of it left out as coplanar with p, so that its
  // polygons facing p hide what it would?
  bool isBehindItsSurface(const WorldPolygon& q, const Vec3& p, double distance, const Box3& lit,
                          double coplanarTolerance) const;

  const PosedScene& scene_;
  const UniformGrid* grid_;
  ClosedObjectFaces closedObjectFaces_;
};

}  // namespace penumbra
