#include "penumbra/dm/surface_casting.h"

#include <algorithm>
#include <cmath>

#include "penumbra/geometry/edge_runs.h"
#include "penumbra/geometry/predicates.h"

namespace penumbra {

std::vector<Polygon3> boundedFan(const CriticalFan& fan, const Box3& sceneBounds) {
  const double reach = 1.01 * sceneBounds.diagonalLength();
  const auto far = [&](const Vec3& s, const Vec3& h) {
    const Vec3 d = h - s;
    return s + d * (1 + reach / length(d));
  };
  const Vec3 far0 = far(fan.source0, fan.hinge0), far1 = far(fan.source1, fan.hinge1);
  // A fixed source: the lines spread from it, one triangle. A fixed hinge: the lines cross there,
  // so the fan is two triangles meeting at the hinge (the quadrilateral would be a bow tie).
  if (fan.source0 == fan.source1) return {{fan.source0, far1, far0}};
  return {{fan.source0, fan.source1, fan.hinge0}, {fan.hinge0, far1, far0}};
}

std::vector<ConvexCut> intersectWithConvex(const Polygon3& p, const Polygon3& convex) {
  std::vector<ConvexCut> out;
  const Vec3 n = normalize(newellNormal(convex));
  const Plane plane{n, dot(n, convex[0])};
  const Vec3 direction = cross(n, newellNormal(p));
  if (squaredLength(direction) == 0) return out;  // parallel or coplanar
  // Signs are exact against the convex polygon's first three vertices. (Scratch vectors kept
  // per thread: casting calls this for every candidate polygon of every surface.)
  thread_local std::vector<Sign> signs;
  thread_local std::vector<double> crossings;
  thread_local std::vector<Vec3> points;
  thread_local std::vector<size_t> order;
  signs.clear();
  crossings.clear();
  points.clear();
  bool below = false, above = false;
  for (const Vec3& v : p) {
    signs.push_back(orientation3d(convex[0], convex[1], convex[2], v));
    below = below || signs.back() == Sign::kNegative;
    above = above || signs.back() == Sign::kPositive;
  }
  // A polygon that only touches the plane (an edge or a vertex on it, the rest on one side) is
  // grazed, not crossed, by the plane's lines: it neither hides an event nor receives one (a
  // shelf whose edge lies in a fan's plane stopped the event there, and the wall behind, lit
  // past that edge, lost it).
  if (!below || !above) return out;
  // Zero counts as positive (symbolic perturbation), so a vertex on the plane is crossed once,
  // never twice.
  const auto negative = [&](size_t i) { return signs[i] == Sign::kNegative; };
  for (size_t i = 0; i < p.size(); ++i) {
    const size_t j = (i + 1) % p.size();
    const Vec3& a = p[i];
    const Vec3& b = p[j];
    if (negative(i) == negative(j)) continue;
    const double da = plane.signedDistance(a), db = plane.signedDistance(b);
    const double t = da == db ? 0.5 : da / (da - db);
    const Vec3 x = a + (b - a) * std::clamp(t, 0.0, 1.0);
    crossings.push_back(dot(x, direction));
    points.push_back(x);
  }
  order.resize(points.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t i, size_t j) { return crossings[i] < crossings[j]; });
  // Inward edge normals of the convex polygon, in its plane.
  for (size_t k = 0; k + 1 < order.size(); k += 2) {
    Vec3 x0 = points[order[k]], x1 = points[order[k + 1]];
    bool empty = false, boundary0 = true, boundary1 = true;
    for (size_t i = 0; i < convex.size() && !empty; ++i) {
      const Vec3& c = convex[i];
      const Vec3 inward = cross(n, convex[(i + 1) % convex.size()] - c);
      const double d0 = dot(x0 - c, inward), d1 = dot(x1 - c, inward);
      if (d0 < 0 && d1 < 0)
        empty = true;
      else if (d0 < 0)
        x0 = x0 + (x1 - x0) * (d0 / (d0 - d1)), boundary0 = false;
      else if (d1 < 0)
        x1 = x1 + (x0 - x1) * (d1 / (d1 - d0)), boundary1 = false;
    }
    if (!empty && !(x0 == x1)) out.push_back({x0, x1, boundary0, boundary1});
  }
  return out;
}

namespace {

// A fan's pieces with their planes. A polygon whose bounds lie farther than `margin` from a
// piece's plane is certainly on one side of the exact plane through the piece's corners (a
// triangle: planar exactly), where intersectWithConvex, whose signs are exact, finds no cut:
// skipping it saves those signs and allocations for most candidates (casting was 14% of
// desk-475's full build). 1e-9 of the scene is far beyond the double plane's rounding (1e-16 of
// the coordinates).
struct FanPieces {
  std::vector<Polygon3> pieces;
  std::vector<Plane> planes;
  double margin = 0;
  FanPieces(const CriticalFan& fan, const UniformGrid& grid)
      : pieces(boundedFan(fan, grid.bounds())), margin(1e-9 * grid.bounds().diagonalLength()) {
    for (const Polygon3& piece : pieces) {
      const Vec3 n = normalize(newellNormal(piece));
      planes.push_back({n, dot(n, piece[0])});
    }
  }
  // Whether piece k's plane passes farther than the margin from every point of the box: then
  // the box holds no point of the piece (those lie within rounding of the plane).
  bool planeMisses(size_t k, const Box3& box) const {
    const auto [low, high] = signedDistanceRange(planes[k], box);
    return low > margin || high < -margin;
  }
  // Appends the polygon's cuts with the pieces, in piece order.
  void appendCuts(const WorldPolygon& polygon, std::vector<SurfaceIntersection>& out) const {
    for (size_t k = 0; k < pieces.size(); ++k) {
      if (planeMisses(k, polygon.bounds)) continue;
      for (const ConvexCut& cut : intersectWithConvex(polygon.vertices, pieces[k]))
        out.push_back({polygon.id, cut.p0, cut.p1, cut.boundaryAt0, cut.boundaryAt1});
    }
  }
};

}  // namespace

void castSurface(DiscontinuitySurface& surface, const PosedScene& scene, const UniformGrid& grid) {
  const FanPieces fan(surface.fan, grid);
  const std::vector<Polygon3>& pieces = fan.pieces;
  surface.cells.clear();
  surface.intersections.clear();
  std::vector<PolygonId> candidates;
  for (size_t k = 0; k < pieces.size(); ++k)
    grid.forEachCellOverlappingBox(boundingBox(pieces[k]), [&](int cell) {
      // Most cells of a piece's box lie off its plane: those the plane misses are skipped before
      // the clip, which would answer no there (its points lie within rounding of the plane).
      const Box3 box = grid.cellBounds(cell);
      if (fan.planeMisses(k, box) || !polygonCutsBox(pieces[k], box)) return;
      surface.cells.push_back(cell);
      const auto& listed = grid.polygonsInCell(cell);
      candidates.insert(candidates.end(), listed.begin(), listed.end());
    });
  std::sort(surface.cells.begin(), surface.cells.end());
  surface.cells.erase(std::unique(surface.cells.begin(), surface.cells.end()), surface.cells.end());
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  for (PolygonId id : candidates)
    if (id != surface.light) fan.appendCuts(scene.polygons[id], surface.intersections);
}

void recastMoved(DiscontinuitySurface& surface, const PosedScene& scene, const UniformGrid& grid,
                 const std::vector<char>& moved, const std::vector<char>& movedCells) {
  std::vector<PolygonId> candidates;
  for (int cell : surface.cells) {
    if (!movedCells[size_t(cell)]) continue;
    for (PolygonId id : grid.polygonsInCell(cell))
      if (moved[size_t(id)] && id != surface.light) candidates.push_back(id);
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  std::vector<SurfaceIntersection> cuts;
  if (!candidates.empty()) {
    const FanPieces fan(surface.fan, grid);
    for (PolygonId id : candidates) fan.appendCuts(scene.polygons[id], cuts);
  }
  // The kept cuts and the new ones, each in polygon order (a polygon's cuts stay together, in
  // the order castSurface makes them).
  std::vector<SurfaceIntersection> merged;
  merged.reserve(surface.intersections.size() + cuts.size());
  size_t next = 0;
  for (const SurfaceIntersection& kept : surface.intersections) {
    if (moved[size_t(kept.polygon)]) continue;
    while (next < cuts.size() && cuts[next].polygon < kept.polygon) merged.push_back(cuts[next++]);
    merged.push_back(kept);
  }
  while (next < cuts.size()) merged.push_back(cuts[next++]);
  surface.intersections = std::move(merged);
}

}  // namespace penumbra
