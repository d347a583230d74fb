#include "penumbra/lighting/exact_reference.h"

#include <polyclipping/clipper.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "penumbra/geometry/edge_runs.h"
#include "penumbra/lighting/form_factor.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

namespace {

// Polygons whose plane passes within this distance (relative to the scene's size) of the point
// cannot hide any solid angle from it: they are skipped (this covers the receiver itself).
constexpr double kCoplanarRelativeTolerance = 1e-12;
// Relative enlargement of the clipping cone beyond the light's hull.
constexpr double kConeMargin = 0.01;
// Corners of the lit light closer than this (relative to its extent) make one corner of the hull;
// far below the margin above, which the hull therefore still covers them by.
constexpr double kDistinctCorners = 1e-9;
// Farthest a projected occluder vertex may lie from the light frame's origin, in units of the lit
// light's extent (inside the cone it is at most 1 + kConeMargin); within Clipper's range.
constexpr double kProjectionReach = 2;
// Integer coordinates: the light's extent maps to 2^60, below Clipper's 2^62 "hi range".
constexpr double kClipperExtent = 1152921504606846976.0;  // 2^60

// Andrew's monotone chain; counter-clockwise, no collinear points.
Polygon2 convexHull(Polygon2 points) {
  std::sort(points.begin(), points.end(),
            [](const Vec2& a, const Vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  if (points.size() < 3) return points;
  Polygon2 hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 1] - hull[k - 2], points[i] - hull[k - 2]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 1] - hull[k - 2], points[i] - hull[k - 2]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

// Per-thread verdicts of ExactReference::isBehindItsSurface, per closed surface, marked with the
// point query they were made for (query numbers only grow, as visit marks do).
struct SurfaceVerdicts {
  std::vector<std::uint64_t> marks;
  std::vector<char> cullable;
  std::uint64_t query = 0;
};
thread_local SurfaceVerdicts surfaceVerdicts;

}  // namespace

ExactReference::ExactReference(const PosedScene& scene, const UniformGrid* grid,
                               ClosedObjectFaces closedObjectFaces)
    : scene_(scene), grid_(grid), closedObjectFaces_(closedObjectFaces) {}

bool ExactReference::isBehindItsSurface(const WorldPolygon& q, const Vec3& p, double distance,
                                        const Box3& lit, double coplanarTolerance) const {
  if (closedObjectFaces_ != ClosedObjectFaces::kFacingThePoint || q.closedSurface < 0) return false;
  // Whether the surface's polygons facing p hide all it hides, decided once per surface and
  // point query (visibleRegion numbers them).
  std::vector<std::uint64_t>& marks = surfaceVerdicts.marks;
  std::vector<char>& cullable = surfaceVerdicts.cullable;
  const size_t s = size_t(q.closedSurface);
  if (marks.size() < scene_.closedSurfaces.size()) {
    marks.resize(scene_.closedSurfaces.size(), 0);
    cullable.resize(scene_.closedSurfaces.size(), 0);
  }
  if (marks[s] != surfaceVerdicts.query) {
    marks[s] = surfaceVerdicts.query;
    const ClosedSurface& surface = scene_.closedSurfaces[s];
    // Outside the surface's bounds a point has winding number 0: exact for p. The lit light's
    // corners come from clipping and its points from the light frame's rounding, so its bounds
    // must clear the surface's by a margin far above that. And every crossing of a segment from
    // p with the surface must be one the boolean operation sees: a polygon whose plane passes
    // within the coplanar tolerance of p is left out, yet a segment may enter the surface
    // through it right beside p (a point a rounding off a box's side at its foot).
    cullable[s] =
        !surface.bounds.contains(p) &&
        !surface.bounds.expanded(1e-9 * scene_.extent.diagonalLength()).overlaps(lit) &&
        std::none_of(surface.polygons.begin(), surface.polygons.end(), [&](PolygonId id) {
          return std::abs(scene_.polygons[size_t(id)].plane.signedDistance(p)) <= coplanarTolerance;
        });
  }
  return cullable[s] && distance < 0;
}

namespace {

// Is the box entirely on the negative side of the plane (n·x < offset everywhere)?
bool isBoxOutside(const Box3& box, const Plane& plane) {
  const Vec3 farthest{plane.normal.x >= 0 ? box.max.x : box.min.x,
                      plane.normal.y >= 0 ? box.max.y : box.min.y,
                      plane.normal.z >= 0 ? box.max.z : box.min.z};
  return plane.signedDistance(farthest) < 0;
}

bool isBoxOutsideAny(const Box3& box, const std::vector<Plane>& planes) {
  for (const Plane& plane : planes)
    if (isBoxOutside(box, plane)) return true;
  return false;
}

// Per-thread visit marks: a polygon listed in several cells is processed once per query.
// Marks only grow, so stale marks of earlier queries (or other scenes) never equal the current one.
struct VisitMarks {
  std::vector<std::uint64_t> marks;
  std::uint64_t current = 0;
};

}  // namespace

template <typename Visit>
void ExactReference::forEachCandidateOccluder(const Box3& shaftBounds,
                                              const std::vector<Plane>& shaftPlanes,
                                              Visit&& visit) const {
  if (!grid_) {
    for (const WorldPolygon& q : scene_.polygons)
      if (q.bounds.overlaps(shaftBounds) && !isBoxOutsideAny(q.bounds, shaftPlanes)) visit(q);
    return;
  }
  thread_local VisitMarks visits;
  if (visits.marks.size() < scene_.polygons.size()) visits.marks.resize(scene_.polygons.size(), 0);
  const std::uint64_t mark = ++visits.current;
  grid_->forEachCellOverlappingBox(shaftBounds, [&](int cell) {
    if (isBoxOutsideAny(grid_->cellBounds(cell), shaftPlanes)) return;
    for (PolygonId id : grid_->polygonsInCell(cell)) {
      if (visits.marks[id] == mark) continue;
      visits.marks[id] = mark;
      const WorldPolygon& q = scene_.polygons[id];
      if (q.bounds.overlaps(shaftBounds) && !isBoxOutsideAny(q.bounds, shaftPlanes)) visit(q);
    }
  });
}

double ExactReference::unoccludedFormFactor(const Vec3& p, const Vec3& n, PolygonId light) const {
  const WorldPolygon& l = scene_.polygons[light];
  if (l.plane.signedDistance(p) <= 0) return 0;  // behind the emitting side
  const Polygon3 clipped = clipByPlane(l.vertices, Plane{n, dot(n, p)});
  return clipped.empty() ? 0 : pointToPolygonFormFactor(p, n, clipped);
}

VisibleLight ExactReference::visibleLight(const Vec3& p, const Vec3& n, PolygonId lightId,
                                          std::optional<PolygonId> receiver) const {
  const WorldPolygon& light = scene_.polygons[lightId];
  VisibleLight result = visibleRegion(
      p, n, light.vertices, light.plane, lightId, receiver,
      [this](const Box3& shaftBounds, const std::vector<Plane>& shaftPlanes, auto&& visit) {
        forEachCandidateOccluder(shaftBounds, shaftPlanes, visit);
      });
  result.light = lightId;
  return result;
}

VisibleLight ExactReference::visiblePart(const Vec3& p, const Vec3& n, const Polygon3& source,
                                         const Plane& sourcePlane, PolygonId sourcePolygon,
                                         std::span<const PolygonId> candidates,
                                         std::optional<PolygonId> receiver) const {
  VisibleLight result = visibleRegion(
      p, n, source, sourcePlane, sourcePolygon, receiver,
      [&](const Box3& shaftBounds, const std::vector<Plane>& shaftPlanes, auto&& visit) {
        for (PolygonId id : candidates) {
          const WorldPolygon& q = scene_.polygons[id];
          if (q.bounds.overlaps(shaftBounds) && !isBoxOutsideAny(q.bounds, shaftPlanes)) visit(q);
        }
      });
  result.light = sourcePolygon;
  return result;
}

double ExactReference::visibleFormFactor(const Vec3& p, const Vec3& n, const Polygon3& source,
                                         const Plane& sourcePlane, PolygonId sourcePolygon,
                                         std::span<const PolygonId> candidates,
                                         std::optional<PolygonId> receiver) const {
  double formFactor = 0;
  for (const Polygon3& ring :
       visiblePart(p, n, source, sourcePlane, sourcePolygon, candidates, receiver).rings)
    formFactor += pointToPolygonFormFactor(p, n, ring);
  return formFactor;
}

std::optional<ExactReference::Cone> ExactReference::coneOf(const Vec3& p, const Vec3& n,
                                                           const Polygon3& source,
                                                           const Plane& lightPlane) const {
  Cone cone;
  cone.pointHeight = lightPlane.signedDistance(p);
  if (cone.pointHeight <= 0) return std::nullopt;  // lights emit from their front side only
  cone.lit = clipByPlane(source, Plane{n, dot(n, p)});
  if (cone.lit.empty()) return std::nullopt;

  cone.frame = PlaneFrame::fromPlane(lightPlane, centroid(source));
  for (const Vec3& x : cone.lit) cone.lit2.push_back(cone.frame.toLocal(x));
  for (const Vec2& q : cone.lit2)
    cone.extent = std::max({cone.extent, std::abs(q.x), std::abs(q.y)});

  // The cone from p through the convex hull of the lit light: every point of it but the apex p is
  // strictly closer to the light plane than p, so an occluder clipped to it projects to a finite
  // place inside the hull (p itself lies on no considered occluder: those are skipped as coplanar).
  // The hull is enlarged by kConeMargin so that the cut lines of occluders lie outside the light:
  // a cut running along a light edge would leave slivers one integer unit wide in the result.
  // Points a rounding apart are one: where p's tangent plane passes through a light corner the
  // clip leaves the corner twice, and the hull's edge between the two copies had a direction of
  // pure rounding noise, so its cone plane could cut through the light's interior and chip the
  // occluders' pieces there (a false gap of light: 0.4-0.6% too much on a box's side whose plane
  // passed through a light corner, under an L-shaped card; Monte Carlo ray casting confirms).
  Polygon2 distinct;
  for (const Vec2& q : cone.lit2)
    if (std::none_of(distinct.begin(), distinct.end(), [&](const Vec2& d) {
          return std::abs(q.x - d.x) <= kDistinctCorners * cone.extent &&
                 std::abs(q.y - d.y) <= kDistinctCorners * cone.extent;
        }))
      distinct.push_back(q);
  Polygon2 hull = convexHull(distinct);
  for (const Vec2& h : hull) cone.hullCenter2 = cone.hullCenter2 + h * (1.0 / double(hull.size()));
  for (Vec2& h : hull) h = cone.hullCenter2 + (h - cone.hullCenter2) * (1 + kConeMargin);
  const Vec3 hullCenter = cone.frame.toWorld(cone.hullCenter2);
  for (size_t i = 0; i < hull.size(); ++i) {
    const Vec3 a = cone.frame.toWorld(hull[i]), b = cone.frame.toWorld(hull[(i + 1) % hull.size()]);
    Vec3 normal = cross(a - p, b - p);
    if (dot(normal, hullCenter - p) < 0) normal = -normal;
    cone.planes.push_back(Plane{normal, dot(normal, p)});  // unnormalized: only signs matter
  }
  cone.planes.push_back(lightPlane);  // only what lies on p's side of the light can hide it
  cone.bounds = boundingBox(cone.lit);
  cone.bounds.extend(p);
  return cone;
}

bool ExactReference::mayOcclude(const Vec3& p, const Vec3& n, PolygonId light,
                                std::span<const Box3> boxes) const {
  const WorldPolygon& source = scene_.polygons[light];
  const auto cone = coneOf(p, n, source.vertices, source.plane);
  if (!cone) return false;
  // The test forEachCandidateOccluder applies to a polygon's bounds: a polygon inside a box
  // passes it only if the box does (each part of it is monotone in the box).
  return std::any_of(boxes.begin(), boxes.end(), [&](const Box3& box) {
    return box.overlaps(cone->bounds) && !isBoxOutsideAny(box, cone->planes);
  });
}

Box3 ExactReference::coneBaseBounds(PolygonId light) const {
  // The hull's vertices h move to c + (h − c)(1 + m) with c inside the lit light: by at most m
  // times the light's diameter, which its bounds' diagonal exceeds.
  const Box3& bounds = scene_.polygons[light].bounds;
  return bounds.expanded(kConeMargin * bounds.diagonalLength());
}

template <typename ForEachCandidate>
VisibleLight ExactReference::visibleRegion(const Vec3& p, const Vec3& n, const Polygon3& source,
                                           const Plane& lightPlane, PolygonId lightId,
                                           std::optional<PolygonId> receiver,
                                           ForEachCandidate&& forEachCandidate) const {
  VisibleLight result;
  const auto coneFound = coneOf(p, n, source, lightPlane);
  if (!coneFound) return result;
  const Cone& coneData = *coneFound;
  const Polygon3& lit = coneData.lit;
  const PlaneFrame& frame = coneData.frame;
  const Polygon2& lit2 = coneData.lit2;
  const double extent = coneData.extent;
  const double pointHeight = coneData.pointHeight;
  const Vec2& hullCenter2 = coneData.hullCenter2;
  const std::vector<Plane>& cone = coneData.planes;
  const Box3& shaft = coneData.bounds;
  const double scale = kClipperExtent / extent;
  const auto toInt = [scale](const Vec2& q) {
    return ClipperLib::IntPoint(ClipperLib::cInt(std::llround(q.x * scale)),
                                ClipperLib::cInt(std::llround(q.y * scale)));
  };
  const double coplanarTolerance = kCoplanarRelativeTolerance * scene_.extent.diagonalLength();

  ClipperLib::Paths occluders;
  const Box3 litBounds = boundingBox(lit);
  ++surfaceVerdicts.query;
  forEachCandidate(shaft, cone, [&](const WorldPolygon& q) {
    if (q.id == lightId || q.id == receiver) return;
    const double distance = q.plane.signedDistance(p);
    if (std::abs(distance) <= coplanarTolerance) return;
    if (isBehindItsSurface(q, p, distance, litBounds, coplanarTolerance)) return;
    // Two buffers reused across polygons and calls: the clipping itself is cheap, allocating
    // a copy of a polygon of many vertices per plane was not.
    // A polygon of many vertices is clipped run by run (edge_runs.h): runs wholly outside a
    // plane are skipped, runs wholly inside carried to the next plane as runs, so the cost
    // follows the part of the polygon near the cone, not the whole polygon.
    thread_local Polygon3 piece, next;
    thread_local std::vector<VertexRun> pieceRuns, nextRuns;
    clipByPlane(q.vertices, q.edgeRuns, cone.front(), piece, pieceRuns);
    for (size_t i = 1; i < cone.size() && !piece.empty(); ++i) {
      clipByPlane(piece, pieceRuns, cone[i], next, nextRuns);
      std::swap(piece, next);
      std::swap(pieceRuns, nextRuns);
    }
    if (piece.empty()) return;
    ClipperLib::Path path;
    path.reserve(piece.size());
    bool inFront = false;
    for (const Vec3& x : piece) {
      // Central projection from p onto the light plane: p + (x − p)·s with n_L·(...) = offset.
      const double drop = pointHeight - lightPlane.signedDistance(x);  // > 0 inside the cone
      inFront = inFront || lightPlane.signedDistance(x) > 0;
      const Vec3 onLight = p + (x - p) * (pointHeight / drop);
      // Inside the cone every projection lies in the enlarged hull; only a piece vertex within
      // rounding of the apex (an occluder touching p) can land elsewhere, its direction being
      // noise. Pull such a point back to the hull's reach so that the integer grid holds it.
      Vec2 local = frame.toLocal(onLight);
      const double reach = std::max(std::abs(local.x), std::abs(local.y));
      if (!(reach <= kProjectionReach * extent))
        local = std::isfinite(reach) ? local * (kProjectionReach * extent / reach) : hullCenter2;
      path.push_back(toInt(local));
    }
    if (!inFront) return;  // a piece lying in the light plane hides nothing
    // Seen from its back a polygon projects clockwise; the union must not let a front and a back
    // face of one solid cancel under the non-zero rule, so every occluder is made positive.
    if (!ClipperLib::Orientation(path)) ClipperLib::ReversePath(path);
    occluders.push_back(std::move(path));
    result.occluders.push_back(q.id);
  });

  if (occluders.empty()) {
    result.rings.push_back(lit);
    return result;
  }
  ClipperLib::Path subject;
  for (const Vec2& q : lit2) subject.push_back(toInt(q));
  ClipperLib::Clipper clipper;
  clipper.AddPath(subject, ClipperLib::ptSubject, true);
  clipper.AddPaths(occluders, ClipperLib::ptClip, true);
  ClipperLib::Paths visible;
  clipper.Execute(ClipperLib::ctDifference, visible, ClipperLib::pftNonZero,
                  ClipperLib::pftNonZero);
  // Touching configurations leave repeated vertices, spikes and zero-area slivers in the output;
  // they carry no area (the integer grid is 2^-60 of the light), so drop them for clean rings.
  ClipperLib::CleanPolygons(visible, 1.5);
  for (const ClipperLib::Path& ring : visible) {
    if (ring.size() < 3 || ClipperLib::Area(ring) == 0) continue;
    Polygon3 ring3;
    ring3.reserve(ring.size());
    for (const ClipperLib::IntPoint& q : ring)
      ring3.push_back(frame.toWorld({double(q.X) / scale, double(q.Y) / scale}));
    result.rings.push_back(std::move(ring3));
  }
  return result;
}

Rgb ExactReference::irradiance(const Vec3& p, const Vec3& n,
                               std::optional<PolygonId> receiver) const {
  Rgb total;
  double exitance = 0;  // the most any point can receive: every light filling its hemisphere
  for (PolygonId lightId : scene_.lights) {
    const VisibleLight visible = visibleLight(p, n, lightId, receiver);
    double formFactor = 0;
    for (const Polygon3& ring : visible.rings) formFactor += pointToPolygonFormFactor(p, n, ring);
    const Rgb& emission = scene_.materialOf(scene_.polygons[lightId]).emission;
    total += emission * formFactor;
    exitance += emission.maxComponent();
  }
  // Lambert's sum over a region of (nearly) nothing, an umbra's sliver or a light seen edge-on,
  // cancels to a few ulps of either sign: what rounding leaves below zero is zero, so that no
  // output is negative. Anything further below zero is left as it is, for the checks to see.
  const double rounding = 1e-12 * exitance;
  for (double Rgb::*channel : {&Rgb::r, &Rgb::g, &Rgb::b})
    if (total.*channel < 0 && total.*channel >= -rounding) total.*channel = 0;
  return total;
}

}  // namespace penumbra
