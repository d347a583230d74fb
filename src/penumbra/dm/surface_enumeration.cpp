#include "penumbra/dm/surface_enumeration.h"

#include "penumbra/base/sort_unique.h"
#include "penumbra/dm/parameter_ranges.h"
#include "penumbra/geometry/predicates.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <tuple>
#include <utility>

namespace penumbra {

namespace {

bool touchesLight(const std::vector<PolygonId>& polygons, PolygonId light) {
  return std::find(polygons.begin(), polygons.end(), light) != polygons.end();
}

// The part of an occluder edge in front of the light (only lines leaving the light's front carry
// light), or nothing when it has none of positive length.
std::optional<std::array<Vec3, 2>> partInFront(const EdgeAdjacency& adjacency,
                                               const SceneEdge& edge, const Plane& lightPlane) {
  Vec3 a = adjacency.position(edge.a), b = adjacency.position(edge.b);
  const double da = lightPlane.signedDistance(a), db = lightPlane.signedDistance(b);
  if (da <= 0 && db <= 0) return std::nullopt;
  if (da <= 0) a = a + (b - a) * (da / (da - db));
  if (db <= 0) b = b + (a - b) * (db / (db - da));
  if (a == b) return std::nullopt;
  return std::array<Vec3, 2>{a, b};
}

// The segment where a plane (normal m through point o) cuts the light polygon: its two extreme
// crossings (the whole trace for a convex light, its hull otherwise: extra lines only refine).
std::optional<std::array<Vec3, 2>> lightTrace(const Polygon3& light, const Vec3& lightNormal,
                                              const Vec3& m, const Vec3& o) {
  const Vec3 along = cross(m, lightNormal);
  if (squaredLength(along) == 0) return std::nullopt;  // the plane is the light's plane
  std::optional<Vec3> lo, hi;
  for (size_t i = 0; i < light.size(); ++i) {
    const Vec3& c = light[i];
    const Vec3& d = light[(i + 1) % light.size()];
    const double dc = dot(m, c - o), dd = dot(m, d - o);
    if ((dc > 0 && dd > 0) || (dc < 0 && dd < 0) || (dc == 0 && dd == 0)) continue;
    const Vec3 x = c + (d - c) * (dc / (dc - dd));
    if (!lo || dot(x, along) < dot(*lo, along)) lo = x;
    if (!hi || dot(x, along) > dot(*hi, along)) hi = x;
  }
  if (!lo || *lo == *hi) return std::nullopt;
  return std::array<Vec3, 2>{*lo, *hi};
}

// The ranges of w in [0, 1] where `holds` is true of the sides g(x, w) = m · ((pivot − S(w)) ×
// (x − pivot)) of the points x against the line through S(w) = s0 + w (s1 − s0) and the pivot, in
// their common plane (normal m). Each side is affine in w, so it changes only where it is zero.
template <class Holds>
std::vector<std::array<double, 2>> sideRanges(const Vec3& pivot, const Vec3& s0, const Vec3& s1,
                                              const Vec3& m, const std::vector<Vec3>& points,
                                              Holds&& holds) {
  const auto g = [&](const Vec3& x, double w) {
    return dot(m, cross(pivot - (s0 + (s1 - s0) * w), x - pivot));
  };
  std::vector<double> breaks{0, 1};
  for (const Vec3& x : points) {
    const double g0 = g(x, 0), g1 = g(x, 1);
    if (g0 != g1 && g0 / (g0 - g1) > 0 && g0 / (g0 - g1) < 1) breaks.push_back(g0 / (g0 - g1));
  }
  std::vector<double> sides(points.size());
  return rangesBetween(std::move(breaks), [&](double w) {
    for (size_t k = 0; k < points.size(); ++k) sides[k] = g(points[k], w);
    return holds(sides);
  });
}

// The ranges where the line through S(w) and v separates a from b (g_a g_b <= 0).
std::vector<std::array<double, 2>> separatingRanges(const Vec3& s0, const Vec3& s1, const Vec3& v,
                                                    const Vec3& a, const Vec3& b, const Vec3& m) {
  return sideRanges(v, s0, s1, m, {a, b},
                    [](const std::vector<double>& g) { return g[0] * g[1] <= 0; });
}

// The ranges where the line of a polygon's plane (normal m) through the light's trace point S(w)
// and `pivot` passes through the polygon (its vertices on both sides; `through`) or only touches
// it at the pivot (all on one side).
std::vector<std::array<double, 2>> pivotRanges(const Vec3& pivot, const Vec3& t0, const Vec3& t1,
                                               const Vec3& m, const Polygon3& vertices,
                                               bool through) {
  return sideRanges(pivot, t0, t1, m, vertices, [&](const std::vector<double>& g) {
    const bool below = std::any_of(g.begin(), g.end(), [](double x) { return x < 0; });
    const bool above = std::any_of(g.begin(), g.end(), [](double x) { return x > 0; });
    return (below && above) == through;
  });
}

// Surfaces by the polygon whose edges gave them, in polygon order (what the memos keep).
using PolygonEntries = std::vector<std::pair<PolygonId, std::vector<DiscontinuitySurface>>>;

// Walks a memo's entries from the frame before (`kept`, by polygon: `polygonOf` names an
// entry's) without those of the moved polygons (`movedPolygons`, ascending), merged in polygon
// order with `moved`, the moved polygons' entries examined again: the entries a fresh examination
// of every polygon would give, where the unmoved ones share no edge with a moved one. Each is
// handed, in that order, to `onKept` or `onMoved`.
template <class Kept, class PolygonOf, class OnKept, class OnMoved>
void forEachMergedWithMoved(Kept& kept, PolygonEntries& moved,
                            const std::vector<PolygonId>& movedPolygons, PolygonOf&& polygonOf,
                            OnKept&& onKept, OnMoved&& onMoved) {
  size_t k = 0;
  for (auto& entry : kept) {
    const PolygonId polygon = polygonOf(entry);
    if (std::binary_search(movedPolygons.begin(), movedPolygons.end(), polygon)) continue;
    for (; k < moved.size() && moved[k].first < polygon; ++k) onMoved(moved[k]);
    onKept(entry);
  }
  for (; k < moved.size(); ++k) onMoved(moved[k]);
}

// The entries forEachMergedWithMoved walks, as one list. The kept entries are moved out (each is
// read once, the frame after).
PolygonEntries mergedWithMoved(PolygonEntries&& kept, PolygonEntries moved,
                               const std::vector<PolygonId>& movedPolygons) {
  PolygonEntries entries;
  const auto take = [&](auto& entry) { entries.push_back(std::move(entry)); };
  forEachMergedWithMoved(
      kept, moved, movedPolygons, [](const auto& entry) { return entry.first; }, take, take);
  return entries;
}

// Appends the entries' surfaces to `surfaces`, numbered on from firstId.
void appendNumbered(const PolygonEntries& entries, SurfaceId firstId,
                    std::vector<DiscontinuitySurface>& surfaces) {
  for (const auto& [id, found] : entries)
    for (DiscontinuitySurface s : found) {
      s.id = firstId + SurfaceId(surfaces.size());
      surfaces.push_back(std::move(s));
    }
}

// Moves the frame before's surfaces first, first + 1, ... (`count` of them) whole, casts
// included, onto `surfaces`, numbered on from firstId, and records where each came from.
void takeOverRun(std::vector<DiscontinuitySurface>& surfacesBefore, SurfaceId first, int count,
                 SurfaceId firstId, std::vector<DiscontinuitySurface>& surfaces,
                 std::vector<int>& takenFrom) {
  for (SurfaceId id = first; id < first + count; ++id) {
    surfaces.push_back(std::move(surfacesBefore[size_t(id)]));
    surfaces.back().id = firstId + SurfaceId(surfaces.size() - 1);
    takenFrom.push_back(int(id));
  }
}

// The moved polygons the grid lists in a region's cells, for an enumeration that reads a memo
// (one test answers for a region far from them); nothing where it reads none.
template <typename Reuse>
std::optional<UniformGrid::ListedPolygons> movedPolygonsListed(const UniformGrid& grid,
                                                               const PosedScene& scene,
                                                               const Reuse* reuse) {
  if (!reuse) return std::nullopt;
  return std::optional<UniformGrid::ListedPolygons>(std::in_place, grid, scene,
                                                    reuse->movedPolygons);
}

}  // namespace

void enumerateEmitterEvSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                                PolygonId light, std::vector<DiscontinuitySurface>& surfaces) {
  const WorldPolygon& lightPolygon = scene.polygons[light];
  const Plane& lightPlane = lightPolygon.plane;
  const Polygon3& lv = lightPolygon.vertices;
  const auto isInFront = [&](const Vec3& p) { return lightPlane.signedDistance(p) > 0; };

  // Light vertex × occluder edge. The hinge edge is clipped to the light's front half-space: only
  // lines leaving the light's front carry light.
  for (const SceneEdge& edge : adjacency.edges()) {
    if (!edge.canBeSilhouette || touchesLight(edge.polygons, light)) continue;
    const auto front = partInFront(adjacency, edge, lightPlane);
    if (!front) continue;
    const auto [a, b] = *front;
    const EdgeId edgeId = EdgeId(&edge - adjacency.edges().data());
    for (size_t i = 0; i < lv.size(); ++i) {
      if (!adjacency.isSilhouetteFrom(edgeId, lv[i])) continue;
      DiscontinuitySurface s;
      s.id = SurfaceId(surfaces.size());
      s.kind = SurfaceKind::kEmitterVertexOccluderEdge;
      s.light = light;
      s.lightFeature = int(i);
      s.occluderFeature = edgeId;
      s.hingePolygons.assign(edge.polygons.begin(), edge.polygons.end());
      s.fan = {lv[i], lv[i], a, b, {}};
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
      s.id = SurfaceId(surfaces.size());
      s.kind = SurfaceKind::kEmitterEdgeOccluderVertex;
      s.light = light;
      s.lightFeature = int(i);
      s.occluderFeature = VertexId(v);
      s.hingePolygons.assign(vertex.polygons.begin(), vertex.polygons.end());
      s.fan = {lv[i], lv[(i + 1) % lv.size()], vertex.position, vertex.position, {}};
      surfaces.push_back(std::move(s));
    }
  }
}

void enumerateNonEmitterEvSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                                   const UniformGrid& grid, PolygonId light, SurfaceId firstId,
                                   std::vector<DiscontinuitySurface>& surfaces,
                                   NonEmitterEvMemo* memo, const NonEmitterEvReuse* reuse) {
  const std::optional<UniformGrid::ListedPolygons> listedMoved =
      movedPolygonsListed(grid, scene, reuse);
  const WorldPolygon& lightPolygon = scene.polygons[light];
  const Plane& lightPlane = lightPolygon.plane;
  const Polygon3& lv = lightPolygon.vertices;
  const double reach = 2 * scene.extent.diagonalLength();
  std::vector<int> seen(adjacency.edges().size(), -1);  // last vertex that examined each edge
  if (memo) memo->byItem.assign(adjacency.vertices().size(), {});

  // The surfaces of vertex vi with the edges of polygon `id` not examined before for vi.
  const auto examine = [&](size_t vi, PolygonId id, std::vector<DiscontinuitySurface>& out) {
    const SceneVertex& vertex = adjacency.vertices()[vi];
    const Vec3& v = vertex.position;
    const std::vector<VertexId>& corners = adjacency.polygonVertices(id);
    for (size_t k = 0; k < corners.size(); ++k) {
      const VertexId ia = corners[k], ib = corners[(k + 1) % corners.size()];
      if (ia == ib || ia == VertexId(vi) || ib == VertexId(vi)) continue;
      const EdgeId edgeId = adjacency.edgeBetween(ia, ib);
      if (edgeId < 0 || seen[edgeId] == int(vi)) continue;
      seen[edgeId] = int(vi);
      const SceneEdge& edge = adjacency.edges()[edgeId];
      if (!edge.canBeSilhouette || touchesLight(edge.polygons, light)) continue;
      if (!adjacency.isSilhouetteFrom(edgeId, v)) continue;
      const auto front = partInFront(adjacency, edge, lightPlane);
      if (!front) continue;
      const auto [a, b] = *front;
      const Vec3 m = cross(b - a, v - a);
      if (squaredLength(m) == 0) continue;
      const auto trace = lightTrace(lv, lightPlane.normal, m, v);
      if (!trace) continue;
      const auto [t0, t1] = *trace;
      for (const auto& [w0, w1] : separatingRanges(t0, t1, v, a, b, m)) {
        DiscontinuitySurface s;
        s.kind = SurfaceKind::kNonEmitterVertexEdge;
        s.light = light;
        s.lightFeature = -1;
        s.occluderFeature = VertexId(vi);
        s.secondFeature = edgeId;
        s.hingePolygons.assign(vertex.polygons.begin(), vertex.polygons.end());
        s.hingePolygons.append(edge.polygons.begin(), edge.polygons.end());
        s.fan = {t0 + (t1 - t0) * w0, t0 + (t1 - t0) * w1, v, v, {}};
        s.fan.contacts = {{a, b}};
        out.push_back(std::move(s));
      }
    }
  };
  using Entries = PolygonEntries;

  for (size_t vi = 0; vi < adjacency.vertices().size(); ++vi) {
    const SceneVertex& vertex = adjacency.vertices()[vi];
    const Vec3& v = vertex.position;
    const double hv = lightPlane.signedDistance(v);
    if (hv <= 0 || touchesLight(vertex.polygons, light)) continue;
    if (!adjacency.canVertexBeSilhouette(VertexId(vi))) continue;
    // Every line from the light through v: the shaft between them and its extension beyond v.
    Box3 region = lightPolygon.bounds;
    region.extend(v);
    for (const Vec3& c : lv) region.extend(v + normalize(v - c) * reach);
    Entries entries;  // (polygon, the surfaces of its edges first examined there), by polygon
    if (reuse && vi < reuse->before.byItem.size() && reuse->unchangedItems[vi]) {
      // The same vertex and region: the polygons that did not move are listed in the same cells
      // and give what they gave (sharing no edge with a moved one, they examine the same edges
      // first); a moved polygon listed in the region's cells now is examined again.
      Entries moved;
      listedMoved->forEachListedInBox(region, [&](PolygonId id) {
        if (id == light) return;
        moved.push_back({id, {}});
        examine(vi, id, moved.back().second);
        if (moved.back().second.empty()) moved.pop_back();
      });
      entries = mergedWithMoved(std::move(reuse->before.byItem[vi]), std::move(moved),
                                reuse->movedPolygons);
      if (memo) ++memo->kept;
    } else {
      for (PolygonId id : grid.polygonsInBox(region)) {
        if (id == light) continue;
        std::vector<DiscontinuitySurface> found;
        examine(vi, id, found);
        if (!found.empty()) entries.push_back({id, std::move(found)});
      }
      if (memo) ++memo->examined;
    }
    appendNumbered(entries, firstId, surfaces);
    if (memo) memo->byItem[vi] = std::move(entries);
  }
}

void enumerateOccluderPlaneSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                                    const UniformGrid& grid, PolygonId light, SurfaceId firstId,
                                    std::vector<DiscontinuitySurface>& surfaces,
                                    OccluderPlaneMemo* memo, const OccluderPlaneReuse* reuse) {
  const double reach = 2 * scene.extent.diagonalLength();
  const std::optional<UniformGrid::ListedPolygons> listedMoved =
      movedPolygonsListed(grid, scene, reuse);
  const WorldPolygon& lightPolygon = scene.polygons[light];
  const Plane& lightPlane = lightPolygon.plane;
  const Polygon3& lv = lightPolygon.vertices;
  // The polygon q that last examined each edge (a stamp: a list of flags over every edge of the
  // scene made for each q was quadratic in the scene).
  std::vector<PolygonId> seen(adjacency.edges().size(), -1);
  if (memo) memo->byItem.assign(scene.polygons.size(), {});
  for (const WorldPolygon& q : scene.polygons) {
    if (q.isLight || q.id == light) continue;
    const std::vector<VertexId>& corners = adjacency.polygonVertices(q.id);
    // Exact sides of the light's vertices against the polygon's plane.
    std::vector<Sign> sides;
    bool above = false, below = false;
    for (const Vec3& c : lv) {
      sides.push_back(orientation3d(q.vertices[0], q.vertices[1], q.vertices[2], c));
      above = above || sides.back() == Sign::kPositive;
      below = below || sides.back() == Sign::kNegative;
    }
    if (!above || !below) continue;
    // Edge-on in these fans: q and its neighbours along its edges only touch them, and the
    // event starts beyond q's far side.
    std::vector<PolygonId> touching{q.id};
    std::vector<std::pair<Vec3, Vec3>> outline;
    for (size_t k = 0; k < corners.size(); ++k) {
      outline.push_back({q.vertices[k], q.vertices[(k + 1) % q.vertices.size()]});
      const EdgeId e = adjacency.edgeBetween(corners[k], corners[(k + 1) % corners.size()]);
      if (e >= 0)
        touching.insert(touching.end(), adjacency.edges()[e].polygons.begin(),
                        adjacency.edges()[e].polygons.end());
    }
    for (size_t i = 0; i < lv.size(); ++i) {
      const size_t j = (i + 1) % lv.size();
      if (sides[i] == sides[j] || sides[i] == Sign::kZero || sides[j] == Sign::kZero) continue;
      const double di = q.plane.signedDistance(lv[i]), dj = q.plane.signedDistance(lv[j]);
      const Vec3 t = lv[i] + (lv[j] - lv[i]) * (di / (di - dj));
      for (size_t k = 0; k < corners.size(); ++k) {
        const EdgeId edgeId = adjacency.edgeBetween(corners[k], corners[(k + 1) % corners.size()]);
        if (edgeId < 0) continue;
        const SceneEdge& edge = adjacency.edges()[edgeId];
        if (!edge.canBeSilhouette || touchesLight(edge.polygons, light)) continue;
        const auto front = partInFront(adjacency, edge, lightPlane);
        if (!front) continue;
        const auto [a, b] = *front;
        if (squaredLength(cross(a - t, b - t)) == 0) continue;
        DiscontinuitySurface s;
        s.id = firstId + SurfaceId(surfaces.size());
        s.kind = SurfaceKind::kLightEdgeOccluderPlane;
        s.light = light;
        s.lightFeature = int(i);
        s.occluderFeature = edgeId;
        s.secondFeature = q.id;
        s.hingePolygons.assign(touching.begin(), touching.end());
        s.fan = {t, t, a, b, {}};
        s.fan.contacts = outline;
        surfaces.push_back(std::move(s));
      }
    }
    // Another occluder's edge crossing q's plane at X: seen from the plane, the crossing of its
    // projection with q's (edge-on) switches between q's edges. The lines of the plane through X
    // that meet the light's trace and pass through q.
    const Vec3 m = q.plane.normal;
    const auto trace = lightTrace(lv, lightPlane.normal, m, q.vertices[0]);
    if (!trace) continue;
    // Named copies, not structured bindings: the lambdas below capture them (clang 14).
    const Vec3 t0 = (*trace)[0], t1 = (*trace)[1];
    Box3 region = lightPolygon.bounds;
    for (const Vec3& x : q.vertices) {
      region.extend(x);
      for (const Vec3& c : lv) region.extend(x + normalize(x - c) * reach);
    }
    // The surfaces through the edges of polygon `id` not examined before for q.
    const auto examine = [&](PolygonId id, std::vector<DiscontinuitySurface>& out) {
      const std::vector<VertexId>& others = adjacency.polygonVertices(id);
      for (size_t k = 0; k < others.size(); ++k) {
        const EdgeId edgeId = adjacency.edgeBetween(others[k], others[(k + 1) % others.size()]);
        if (edgeId < 0 || seen[edgeId] == q.id) continue;
        seen[edgeId] = q.id;
        const SceneEdge& edge = adjacency.edges()[edgeId];
        if (!edge.canBeSilhouette || touchesLight(edge.polygons, light)) continue;
        const Vec3 a = adjacency.position(edge.a), b = adjacency.position(edge.b);
        const Sign sa = orientation3d(q.vertices[0], q.vertices[1], q.vertices[2], a);
        const Sign sb = orientation3d(q.vertices[0], q.vertices[1], q.vertices[2], b);
        if (sa == sb || sa == Sign::kZero || sb == Sign::kZero) continue;  // no proper crossing
        const double da = q.plane.signedDistance(a), db = q.plane.signedDistance(b);
        const Vec3 x = a + (b - a) * (da / (da - db));
        if (lightPlane.signedDistance(x) <= 0) continue;
        // The w where the line through S(w) and x passes through q.
        for (const auto& [w0, w1] : pivotRanges(x, t0, t1, m, q.vertices, true)) {
          DiscontinuitySurface s;
          s.kind = SurfaceKind::kOccluderPlaneOccluderEdge;
          s.light = light;
          s.lightFeature = -1;
          s.occluderFeature = edgeId;
          s.secondFeature = q.id;
          s.hingePolygons.assign(touching.begin(), touching.end());
          s.hingePolygons.append(edge.polygons.begin(), edge.polygons.end());
          s.fan = {t0 + (t1 - t0) * w0, t0 + (t1 - t0) * w1, x, x, outline};
          out.push_back(std::move(s));
        }
      }
    };
    const auto examined = [&](PolygonId id, PolygonEntries& entries) {
      if (id == light || std::count(touching.begin(), touching.end(), id)) return;
      entries.push_back({id, {}});
      examine(id, entries.back().second);
      if (entries.back().second.empty()) entries.pop_back();
    };
    PolygonEntries entries;  // (polygon, the surfaces of its edges first examined there)
    const size_t qi = size_t(q.id);
    if (reuse && qi < reuse->before.byItem.size() && reuse->unchangedItems[qi]) {
      // The same polygon, light and region: the polygons that did not move are listed in the
      // same cells and give what they gave (sharing no edge with a moved one, they examine the
      // same edges first); a moved polygon listed in the region's cells now is examined again.
      PolygonEntries moved;
      listedMoved->forEachListedInBox(region, [&](PolygonId id) { examined(id, moved); });
      entries = mergedWithMoved(std::move(reuse->before.byItem[qi]), std::move(moved),
                                reuse->movedPolygons);
      if (memo) ++memo->kept;
    } else {
      for (PolygonId id : grid.polygonsInBox(region)) examined(id, entries);
      if (memo) ++memo->examined;
    }
    appendNumbered(entries, firstId, surfaces);
    if (memo) memo->byItem[qi] = std::move(entries);
    // Seen from q's plane, q's projection is a segment on the light's trace; crossing the plane
    // flips it over, wherever that segment overlaps the lit part of the trace. The fans from T
    // above hold the points from which it covers an end of the trace; the points from which it
    // lies inside the trace see its ends at q's vertices: the lines of the plane through a
    // vertex V, tangent to q there, that meet the trace.
    for (size_t k = 0; k < corners.size(); ++k) {
      const Vec3& v = q.vertices[k];
      if (lightPlane.signedDistance(v) <= 0) continue;
      std::vector<PolygonId> hinge = touching;
      const std::vector<PolygonId>& atVertex = adjacency.vertices()[corners[k]].polygons;
      hinge.insert(hinge.end(), atVertex.begin(), atVertex.end());
      for (const auto& [w0, w1] : pivotRanges(v, t0, t1, m, q.vertices, false)) {
        DiscontinuitySurface s;
        s.id = firstId + SurfaceId(surfaces.size());
        s.kind = SurfaceKind::kOccluderPlaneOccluderVertex;
        s.light = light;
        s.lightFeature = -1;
        s.occluderFeature = corners[k];
        s.secondFeature = q.id;
        s.hingePolygons.assign(hinge.begin(), hinge.end());
        s.fan = {t0 + (t1 - t0) * w0, t0 + (t1 - t0) * w1, v, v, outline};
        surfaces.push_back(std::move(s));
      }
    }
  }
}

void coplanarEdgeSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                          const std::vector<CoplanarEdgePair>& pairs, PolygonId light,
                          SurfaceId firstId, std::vector<DiscontinuitySurface>& surfaces) {
  const WorldPolygon& lightPolygon = scene.polygons[light];
  const Polygon3& lv = lightPolygon.vertices;
  for (const CoplanarEdgePair& pair : pairs) {
    const SceneEdge &first = adjacency.edges()[pair.first],
                    &second = adjacency.edges()[pair.second];
    const Vec3 a = adjacency.position(first.a), b = adjacency.position(first.b);
    const Vec3 c = adjacency.position(second.a), d = adjacency.position(second.b);
    // Both wholly in front of the light (an edge crossing its plane is left to the other events).
    if (lightPolygon.plane.signedDistance(a) <= 0 || lightPolygon.plane.signedDistance(b) <= 0 ||
        lightPolygon.plane.signedDistance(c) <= 0 || lightPolygon.plane.signedDistance(d) <= 0)
      continue;
    // The pair's plane: through the first edge and the second edge's farther endpoint.
    const Vec3 far =
        squaredLength(cross(b - a, c - a)) > squaredLength(cross(b - a, d - a)) ? c : d;
    const Vec3& l0 = lv[pair.lightEdge];
    const Vec3& l1 = lv[(pair.lightEdge + 1) % lv.size()];
    const Sign s0 = orientation3d(a, b, far, l0), s1 = orientation3d(a, b, far, l1);
    if (s0 == s1 || s0 == Sign::kZero || s1 == Sign::kZero) continue;
    const Vec3 m = cross(b - a, far - a);
    const double h0 = dot(m, l0 - a), h1 = dot(m, l1 - a);
    const Vec3 t = l0 + (l1 - l0) * (h0 / (h0 - h1));
    if (!adjacency.isSilhouetteFrom(pair.first, t) || !adjacency.isSilhouetteFrom(pair.second, t))
      continue;
    // The first edge's parameters u where the lines from T through the second's endpoints cross
    // it; both must lie ahead of T on their line.
    const Vec3 e = b - a;
    std::array<double, 2> us{};
    bool ahead = true;
    for (int k = 0; k < 2; ++k) {
      const Vec3 direction = (k == 0 ? c : d) - t;
      const double denominator = dot(m, cross(e, direction));
      if (denominator == 0) {
        ahead = false;
        break;
      }
      us[k] = dot(m, cross(direction, a - t)) / denominator;
      const double along = dot(m, cross(a - t, e)) / dot(m, cross(direction, e));
      ahead = ahead && along > 0;
    }
    if (!ahead) continue;
    const double u0 = std::max(0.0, std::min(us[0], us[1]));
    const double u1 = std::min(1.0, std::max(us[0], us[1]));
    if (!(u0 < u1)) continue;
    DiscontinuitySurface s;
    s.id = firstId + SurfaceId(surfaces.size());
    s.kind = SurfaceKind::kLightEdgeCoplanarEdges;
    s.light = light;
    s.lightFeature = pair.lightEdge;
    s.occluderFeature = pair.first;
    s.secondFeature = pair.second;
    s.hingePolygons.assign(first.polygons.begin(), first.polygons.end());
    s.hingePolygons.append(second.polygons.begin(), second.polygons.end());
    s.fan = {t, t, a + e * u0, a + e * u1, {{c, d}}};
    surfaces.push_back(std::move(s));
  }
}

void coplanarEdgeCrossingSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                                  const UniformGrid& grid,
                                  const std::vector<CoplanarEdgePair>& pairs, PolygonId light,
                                  SurfaceId firstId, std::vector<DiscontinuitySurface>& surfaces,
                                  CoplanarCrossingMemo* memo, const CoplanarCrossingReuse* reuse) {
  const double reach = 2 * scene.extent.diagonalLength();
  const WorldPolygon& lightPolygon = scene.polygons[light];
  const Plane& lightPlane = lightPolygon.plane;
  const Polygon3& lv = lightPolygon.vertices;
  // A pair comes once per light edge it was found with; its fans do not depend on the edge.
  // Ascending, as one key each (the lower edge's id in the high half).
  std::vector<std::uint64_t> unique;
  unique.reserve(pairs.size());
  for (const CoplanarEdgePair& pair : pairs) {
    const auto [low, high] = std::minmax(pair.first, pair.second);
    unique.push_back(std::uint64_t(std::uint32_t(low)) << 32 | std::uint32_t(high));
  }
  sortUnique(unique);
  const std::optional<UniformGrid::ListedPolygons> listedMoved =
      movedPolygonsListed(grid, scene, reuse);
  // The pair that last examined each edge (a stamp, not a flag cleared per pair: clearing a
  // flag per edge of the scene for each of thousands of pairs was quadratic).
  std::vector<int> seen(adjacency.edges().size(), -1);
  int stamp = -1;
  if (memo) memo->pairs.clear();
  using Entries = PolygonEntries;
  for (const std::uint64_t key : unique) {
    const std::pair<EdgeId, EdgeId> pair{EdgeId(key >> 32), EdgeId(key & 0xffffffffu)};
    // The frame before's entry for the pair, where its two edges are as they were.
    const CoplanarCrossingMemo::Pair* before = nullptr;
    if (reuse && reuse->unchangedEdges[size_t(pair.first)] &&
        reuse->unchangedEdges[size_t(pair.second)]) {
      const auto& kept = reuse->before.pairs;
      const auto it = std::lower_bound(kept.begin(), kept.end(), pair,
                                       [](const CoplanarCrossingMemo::Pair& k, const auto& p) {
                                         return std::pair(k.first, k.second) < p;
                                       });
      if (it != kept.end() && it->first == pair.first && it->second == pair.second) before = &*it;
    }
    // The pair's surfaces, numbered on, by polygon: those found now, and those of the frame
    // before taken over whole.
    std::vector<SurfaceRun> runs;
    const auto append = [&](PolygonId polygon, std::vector<DiscontinuitySurface>& found) {
      runs.push_back({polygon, firstId + SurfaceId(surfaces.size()), int(found.size())});
      for (DiscontinuitySurface& s : found) {
        s.id = firstId + SurfaceId(surfaces.size());
        surfaces.push_back(std::move(s));
        if (reuse) reuse->takenFrom.push_back(-1);
      }
    };
    // The frame before's runs merged with the surfaces found now on the moved polygons (a moved
    // polygon listed in the region before and not now gave surfaces then: dropped). Each pair of
    // the frame before is read once (the pairs are unique).
    const auto takeOverMergedWith = [&](PolygonEntries& moved) {
      forEachMergedWithMoved(
          before->entries, moved, reuse->movedPolygons,
          [](const SurfaceRun& run) { return run.polygon; },
          [&](const SurfaceRun& run) {
            runs.push_back({run.polygon, firstId + SurfaceId(surfaces.size()), run.count});
            takeOverRun(reuse->surfacesBefore, run.first, run.count, firstId, surfaces,
                        reuse->takenFrom);
          },
          [&](auto& entry) { append(entry.first, entry.second); });
      if (memo) ++memo->keptPairs;
    };
    // Its region is a function of its edges and the light, the same as then: the polygons that
    // did not move are listed in the same cells and give what they gave (sharing no edge with a
    // moved one, they examine the same edges first). Only the moved polygons listed there now are
    // examined again; where there are none, the pair's plane and region are not computed.
    std::vector<PolygonId> movedInRegion;
    if (before) {
      listedMoved->forEachListedInBox(before->region,
                                      [&](PolygonId id) { movedInRegion.push_back(id); });
      if (movedInRegion.empty()) {
        PolygonEntries none;
        takeOverMergedWith(none);
        if (memo) memo->pairs.push_back({pair.first, pair.second, std::move(runs), before->region});
        continue;
      }
    }
    const EdgeId firstEdge = pair.first;
    const SceneEdge &first = adjacency.edges()[pair.first],
                    &second = adjacency.edges()[pair.second];
    const auto firstFront = partInFront(adjacency, first, lightPlane);
    const auto secondFront = partInFront(adjacency, second, lightPlane);
    if (!firstFront || !secondFront) continue;
    // Named copies, not structured bindings: the lambdas below capture them (clang 14).
    const Vec3 a = (*firstFront)[0], b = (*firstFront)[1];
    const Vec3 c = (*secondFront)[0], d = (*secondFront)[1];
    // The pair's plane, through the first edge and the second's endpoint farther from its line.
    const Vec3 far =
        squaredLength(cross(b - a, c - a)) > squaredLength(cross(b - a, d - a)) ? c : d;
    const Vec3 m = cross(b - a, far - a);
    if (squaredLength(m) == 0) continue;  // collinear edges: no plane of their own
    const auto trace = lightTrace(lv, lightPlane.normal, m, a);
    if (!trace) continue;
    const Vec3 t0 = (*trace)[0], t1 = (*trace)[1];
    // The two edges' polygons meet the plane only along the edges' lines, so their other edges
    // cross it (if at all) at the edges' ends: those events are the non-emitter EV fans.
    std::vector<PolygonId> touching = first.polygons;
    touching.insert(touching.end(), second.polygons.begin(), second.polygons.end());
    // X lies on a line from the trace through both edges: within the bounds of the lines from
    // the trace through each edge (up to the scene's reach), padded against rounding.
    const auto swept = [&](const Vec3& p, const Vec3& q) {
      Box3 box;
      for (const Vec3& x : {p, q})
        for (const Vec3& t : {t0, t1}) {
          box.extend(t);
          box.extend(x);
          if (!(x == t)) box.extend(x + normalize(x - t) * reach);  // an end on the light plane
        }
      return box;
    };
    const Box3 byFirst = swept(a, b), bySecond = swept(c, d);
    const Vec3 pad = Vec3{1, 1, 1} * (1e-6 * scene.extent.diagonalLength());
    const Box3 region{componentMax(byFirst.min, bySecond.min) - pad,
                      componentMin(byFirst.max, bySecond.max) + pad};
    if (region.isEmpty()) continue;
    // The surfaces through the edges of polygon `id` not examined before for this pair.
    const auto examine = [&](PolygonId id, std::vector<DiscontinuitySurface>& out) {
      adjacency.forEachEdgeOf(id, [&](EdgeId edgeId) {
        if (seen[size_t(edgeId)] == stamp) return;
        seen[size_t(edgeId)] = stamp;
        const SceneEdge& edge = adjacency.edges()[edgeId];
        if (!edge.canBeSilhouette || touchesLight(edge.polygons, light)) return;
        const Vec3 p = adjacency.position(edge.a), q = adjacency.position(edge.b);
        const Sign sp = orientation3d(a, b, far, p), sq = orientation3d(a, b, far, q);
        if (sp == sq || sp == Sign::kZero || sq == Sign::kZero) return;  // no proper crossing
        const double dp = dot(m, p - a), dq = dot(m, q - a);
        const Vec3 x = p + (q - p) * (dp / (dp - dq));
        if (lightPlane.signedDistance(x) <= 0) return;
        const auto meetsBoth = [](const std::vector<double>& g) {
          return g[0] * g[1] <= 0 && g[2] * g[3] <= 0;
        };
        for (const auto& [w0, w1] : sideRanges(x, t0, t1, m, {a, b, c, d}, meetsBoth)) {
          DiscontinuitySurface s;
          s.kind = SurfaceKind::kCoplanarEdgesOccluderCrossing;
          s.light = light;
          s.lightFeature = -1;
          s.occluderFeature = edgeId;
          s.secondFeature = firstEdge;
          s.hingePolygons.assign(touching.begin(), touching.end());
          s.hingePolygons.append(edge.polygons.begin(), edge.polygons.end());
          s.fan = {t0 + (t1 - t0) * w0, t0 + (t1 - t0) * w1, x, x, {{a, b}, {c, d}}};
          out.push_back(std::move(s));
        }
      });
    };
    // A polygon whose bounds lie wholly on one side of the pair's plane (past what rounding m and
    // the distances could move) has no edge crossing it: skipped without the exact tests, as
    // examining it would find nothing (an edge it shares is found, or not, the same way later).
    const double mLength = length(m);
    const auto whollyOnOneSide = [&](const Box3& box) {
      const Vec3 centre = (box.min + box.max) * 0.5, half = (box.max - box.min) * 0.5;
      const double d = dot(m, centre - a);
      const double r = std::abs(m.x) * half.x + std::abs(m.y) * half.y + std::abs(m.z) * half.z;
      return std::abs(d) > r + 1e-9 * mLength * (length(centre - a) + length(half));
    };
    const auto examined = [&](PolygonId id, Entries& entries) {
      if (id == light || std::count(touching.begin(), touching.end(), id)) return;
      if (whollyOnOneSide(scene.polygons[id].bounds)) return;
      entries.push_back({id, {}});
      examine(id, entries.back().second);
      if (entries.back().second.empty()) entries.pop_back();
    };
    ++stamp;
    if (before) {
      Entries moved;
      for (PolygonId id : movedInRegion) examined(id, moved);
      takeOverMergedWith(moved);
    } else {
      Entries entries;  // (polygon, the surfaces of its edges first examined there), by polygon
      for (PolygonId id : grid.polygonsInBox(region)) examined(id, entries);
      for (auto& [id, found] : entries) append(id, found);
      if (memo) ++memo->examinedPairs;
    }
    if (memo) memo->pairs.push_back({pair.first, pair.second, std::move(runs), region});
  }
}

void parallelEdgeCrossingSurfaces(const PosedScene& scene, const EdgeAdjacency& adjacency,
                                  const std::vector<DiscontinuitySurface>& evSurfaces,
                                  PolygonId light, SurfaceId firstId,
                                  std::vector<DiscontinuitySurface>& surfaces,
                                  ParallelCrossingMemo* memo, const ParallelCrossingReuse* reuse) {
  const WorldPolygon& lightPolygon = scene.polygons[light];
  const Polygon3& lv = lightPolygon.vertices;
  const size_t n = lv.size();
  // The planes of a light edge and an occluder edge, each with its fans in order: a fan of light
  // vertex i and occluder edge E gives the planes of E with the light edges i - 1 and i where E
  // lies in one plane with them. Sorted by light edge then occluder edge (stable: the fans of a
  // plane stay in their order).
  struct FanOfPlane {
    size_t lightEdge = 0;
    EdgeId edge = 0;
    size_t fan = 0;
  };
  std::vector<FanOfPlane> fansOfPlanes;
  for (size_t k = 0; k < evSurfaces.size(); ++k) {
    const DiscontinuitySurface& fan = evSurfaces[k];
    if (fan.light != light || fan.kind != SurfaceKind::kEmitterVertexOccluderEdge) continue;
    const SceneEdge& edge = adjacency.edges()[fan.occluderFeature];
    const auto front = partInFront(adjacency, edge, lightPolygon.plane);
    if (!front) continue;
    const auto [a, b] = *front;
    const size_t i = size_t(fan.lightFeature);
    for (const size_t lightEdge : {(i + n - 1) % n, i}) {
      const Vec3 &s0 = lv[lightEdge], &s1 = lv[(lightEdge + 1) % n];
      if (orientation3d(s0, s1, adjacency.position(edge.a), adjacency.position(edge.b)) !=
          Sign::kZero)
        continue;
      // On the light edge's line: no plane. One end on it (a card standing on the light's edge)
      // still makes one, through the other end.
      if (squaredLength(cross(s1 - s0, a - s0)) == 0 && squaredLength(cross(s1 - s0, b - s0)) == 0)
        continue;
      fansOfPlanes.push_back({lightEdge, EdgeId(fan.occluderFeature), k});
    }
  }
  std::stable_sort(fansOfPlanes.begin(), fansOfPlanes.end(),
                   [](const FanOfPlane& p, const FanOfPlane& q) {
                     return std::tie(p.lightEdge, p.edge) < std::tie(q.lightEdge, q.edge);
                   });
  // The frame before's plane with the same light edge and occluder edge whose fans are, in order,
  // those these fans have the cuts of.
  const auto keptPlane = [&](size_t lightEdge, const SceneEdge& edge, size_t begin,
                             size_t end) -> std::optional<size_t> {
    if (!reuse) return std::nullopt;
    const auto sameCutsAs = [&](size_t j) {
      const size_t fan = fansOfPlanes[j].fan;
      return fan < reuse->sameCutsAs.size() ? reuse->sameCutsAs[fan] : -1;
    };
    const int first = sameCutsAs(begin);
    if (first < 0) return std::nullopt;
    const auto& byFirstFan = reuse->before.byFirstFan;
    for (auto it = std::lower_bound(byFirstFan.begin(), byFirstFan.end(),
                                    std::pair<size_t, size_t>{size_t(first), 0});
         it != byFirstFan.end() && it->first == size_t(first); ++it) {
      const ParallelCrossingMemo::Plane& plane = reuse->before.planes[it->second];
      if (plane.lightEdge != int(lightEdge) || plane.fans.size() != end - begin ||
          plane.a != adjacency.position(edge.a) || plane.b != adjacency.position(edge.b) ||
          plane.polygons != edge.polygons)
        continue;
      bool same = true;
      for (size_t j = begin; same && j < end; ++j)
        same = sameCutsAs(j) == int(plane.fans[j - begin]);
      if (same) return it->second;
    }
    return std::nullopt;
  };
  const double apart = 1e-9 * scene.extent.diagonalLength();
  for (size_t begin = 0; begin < fansOfPlanes.size();) {
    const size_t lightEdge = fansOfPlanes[begin].lightEdge;
    const EdgeId edgeId = fansOfPlanes[begin].edge;
    size_t end = begin;
    while (end < fansOfPlanes.size() && fansOfPlanes[end].lightEdge == lightEdge &&
           fansOfPlanes[end].edge == edgeId)
      ++end;
    const SceneEdge& edge = adjacency.edges()[edgeId];
    const SurfaceId first = firstId + SurfaceId(surfaces.size());
    if (const std::optional<size_t> kept = keptPlane(lightEdge, edge, begin, end)) {
      // Distinct fans have the cuts of distinct fans of the frame before, and two planes share
      // no fan with the same light edge: no plane of the frame before is taken twice.
      const ParallelCrossingMemo::Plane& before = reuse->before.planes[*kept];
      takeOverRun(reuse->surfacesBefore, before.first, before.count, firstId, surfaces,
                  reuse->takenFrom);
      for (size_t k = surfaces.size() - size_t(before.count); k < surfaces.size(); ++k)
        surfaces[k].occluderFeature = edgeId;
      if (memo) ++memo->keptPlanes;
    } else {
      if (memo) ++memo->examinedPlanes;
      const auto [a, b] = *partInFront(adjacency, edge, lightPolygon.plane);
      // The points X of the plane. Both light vertices of the light edge have a fan of that
      // plane, and each finds X against its own bounded fan, a rounding apart; an edge crossing
      // the plane gives X once for each of its polygons. One fan per X, with all of them as hinge
      // polygons (a polygon through X left out would cut the lines there). Every crossing found,
      // as a flat list sorted by its point's key (stable: a crossing's point is the one found
      // first, its polygons in the order found).
      using Key = std::array<long long, 3>;
      struct Found {
        Key key;
        Vec3 x;
        PolygonId polygon;
      };
      std::vector<Found> found;
      for (size_t j = begin; j < end; ++j)
        for (const SurfaceIntersection& cut : evSurfaces[fansOfPlanes[j].fan].intersections) {
          if (std::count(edge.polygons.begin(), edge.polygons.end(), cut.polygon)) continue;
          for (int side = 0; side < 2; ++side) {
            if (!(side == 0 ? cut.boundaryAt0 : cut.boundaryAt1)) continue;
            const Vec3 x = side == 0 ? cut.p0 : cut.p1;
            if (lightPolygon.plane.signedDistance(x) <= 0) continue;
            found.push_back(
                {{std::llround(x.x / apart), std::llround(x.y / apart), std::llround(x.z / apart)},
                 x,
                 cut.polygon});
          }
        }
      std::stable_sort(found.begin(), found.end(),
                       [](const Found& p, const Found& q) { return p.key < q.key; });
      const Vec3 &s0 = lv[lightEdge], &s1 = lv[(lightEdge + 1) % n];
      // The common plane, through the end of the occluder edge farther from the light edge's
      // line.
      const Vec3 ma = cross(s1 - s0, a - s0), mb = cross(s1 - s0, b - s0);
      const Vec3 m = squaredLength(ma) >= squaredLength(mb) ? ma : mb;
      for (size_t k = 0; k < found.size();) {
        const Found& x = found[k];
        std::vector<PolygonId> polygons;
        for (; k < found.size() && found[k].key == x.key; ++k)
          if (!std::count(polygons.begin(), polygons.end(), found[k].polygon))
            polygons.push_back(found[k].polygon);
        for (const auto& [w0, w1] : separatingRanges(s0, s1, x.x, a, b, m)) {
          DiscontinuitySurface s;
          s.id = firstId + SurfaceId(surfaces.size());
          s.kind = SurfaceKind::kLightEdgeParallelEdgeCrossing;
          s.light = light;
          s.lightFeature = int(lightEdge);
          s.occluderFeature = edgeId;
          s.secondFeature = polygons.front();
          s.hingePolygons.assign(edge.polygons.begin(), edge.polygons.end());
          s.hingePolygons.append(polygons.begin(), polygons.end());
          s.fan = {s0 + (s1 - s0) * w0, s0 + (s1 - s0) * w1, x.x, x.x, {{a, b}}};
          surfaces.push_back(std::move(s));
          if (reuse) reuse->takenFrom.push_back(-1);
        }
      }
    }
    if (memo) {
      ParallelCrossingMemo::Plane made{int(lightEdge),
                                       adjacency.position(edge.a),
                                       adjacency.position(edge.b),
                                       edge.polygons,
                                       {},
                                       first,
                                       int(firstId + SurfaceId(surfaces.size()) - first)};
      for (size_t j = begin; j < end; ++j) made.fans.push_back(fansOfPlanes[j].fan);
      memo->planes.push_back(std::move(made));
    }
    begin = end;
  }
  if (memo) {
    for (size_t j = 0; j < memo->planes.size(); ++j)
      memo->byFirstFan.push_back({memo->planes[j].fans.front(), j});
    std::sort(memo->byFirstFan.begin(), memo->byFirstFan.end());
  }
}

}  // namespace penumbra
