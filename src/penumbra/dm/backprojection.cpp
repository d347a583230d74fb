#include "penumbra/dm/backprojection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>

#include "penumbra/geometry/edge_runs.h"
#include "penumbra/geometry/segment_distance.h"
#include "penumbra/lighting/form_factor.h"

namespace penumbra {

namespace {

struct Segment {
  Vec3 a, b;
  FeatureRef ref;
};

// Which feature lines pass through a point of the visible region.
enum class LineKind { kLightEdge, kHorizon, kOccluderEdge };
struct LineHit {
  LineKind kind;
  int lightEdge = 0;
  FeatureRef edge;
};

// Does the ray from p through x (x on the light plane) pass through segment ab within `tolerance`
// (measured on the light plane), between p and x?
bool projectsThrough(const Vec3& p, const Vec3& x, const Vec3& a, const Vec3& b, double tolerance) {
  const Vec3 d1 = x - p, d2 = b - a, r = p - a;
  const double aa = dot(d1, d1), bb = dot(d1, d2), cc = dot(d2, d2), dd = dot(d1, r),
               ee = dot(d2, r);
  const double den = aa * cc - bb * bb;
  if (den <= 0) return false;  // parallel
  const double s = (bb * ee - cc * dd) / den;
  const double t = (aa * ee - bb * dd) / den;
  if (s <= 0 || s >= 1 + 1e-12 || t < -1e-9 || t > 1 + 1e-9) return false;
  // Gap between the lines at the closest points, magnified onto the light plane by 1/s.
  const Vec3 gap = (p + d1 * s) - (a + d2 * t);
  return length(gap) / s <= tolerance;
}

Vec3 intersectThreePlanes(const Vec3& n1, double d1, const Vec3& n2, double d2, const Vec3& n3,
                          double d3) {
  const Vec3 c23 = cross(n2, n3), c31 = cross(n3, n1), c12 = cross(n1, n2);
  return (c23 * d1 + c31 * d2 + c12 * d3) / dot(n1, c23);
}

Vec3 linePlane(const Vec3& c, const Vec3& d, const Vec3& normal, double offset) {
  const double t = (offset - dot(normal, c)) / dot(normal, d - c);
  return c + (d - c) * t;
}

// A shared edge is one line: keeps the first of the edges with the same two ends (either way
// round), in their order.
void withoutRepeatedEdges(std::vector<Segment>& edges) {
  using Key = std::array<double, 6>;
  const auto keyOf = [](const Segment& e) {
    const auto lexLess = [](const Vec3& u, const Vec3& v) {
      return std::tie(u.x, u.y, u.z) < std::tie(v.x, v.y, v.z);
    };
    const Vec3& lo = lexLess(e.a, e.b) ? e.a : e.b;
    const Vec3& hi = lexLess(e.a, e.b) ? e.b : e.a;
    return Key{lo.x, lo.y, lo.z, hi.x, hi.y, hi.z};
  };
  std::vector<std::pair<Key, size_t>> keys;
  keys.reserve(edges.size());
  for (size_t i = 0; i < edges.size(); ++i) keys.push_back({keyOf(edges[i]), i});
  std::sort(keys.begin(), keys.end());
  std::vector<char> repeated(edges.size(), 0);
  for (size_t i = 1; i < keys.size(); ++i)
    if (keys[i].first == keys[i - 1].first) repeated[keys[i].second] = 1;
  size_t kept = 0;
  for (size_t i = 0; i < edges.size(); ++i)
    if (!repeated[i]) edges[kept++] = edges[i];
  edges.resize(kept);
}

// The rectangle bounding a visible region's rings in the light plane's frame, and the cone from
// the point over it. A ring vertex x is labelled by an occluder edge only if the ray from p to x
// passes within tolerance·s of it (projectsThrough, s ≤ 1 + 1e-12 the ray's parameter), so only
// if the edge comes within that distance of the cone: an edge lying beyond one of the cone's
// side planes by more than `margin` (≥ the tolerance, plus rounding) cannot label any vertex.
// Likewise a projected occluder vertex farther than `margin` outside the rectangle.
struct RingBounds {
  PlaneFrame frame;
  Vec2 low, high;
  std::array<Plane, 4> sides{};  // through the apex, unit normals pointing out of the cone
  bool hasCone = false;
  double margin = 0;

  // Which side planes the point lies beyond by more than the margin, one bit each: an edge
  // whose ends share a bit is separated from the cone, a vertex with any bit projects outside.
  unsigned outsideMask(const Vec3& x) const {
    if (!hasCone) return 0;
    unsigned mask = 0;
    for (int i = 0; i < 4; ++i) mask |= sides[i].signedDistance(x) > margin ? 1u << i : 0u;
    return mask;
  }
  // Whether every point of the box has a bit set (the same one): then every edge of a run inside
  // it is separated and every vertex projects outside, as testing each would find.
  bool separates(const Box3& box) const {
    if (!hasCone) return false;
    return std::any_of(sides.begin(), sides.end(), [&](const Plane& side) {
      return signedDistanceRange(side, box).first > margin;
    });
  }
  bool holds(const Vec3& onLightPlane) const {
    const Vec2 q = frame.toLocal(onLightPlane);
    return q.x >= low.x - margin && q.x <= high.x + margin && q.y >= low.y - margin &&
           q.y <= high.y + margin;
  }
};

RingBounds ringBoundsOf(const std::vector<Polygon3>& rings, const Plane& lightPlane,
                        const Vec3& apex, double margin) {
  RingBounds bounds;
  bounds.frame = PlaneFrame::fromPlane(lightPlane, rings.front().front());
  bounds.margin = margin;
  const double inf = std::numeric_limits<double>::infinity();
  bounds.low = {inf, inf};
  bounds.high = {-inf, -inf};
  for (const Polygon3& ring : rings)
    for (const Vec3& x : ring) {
      const Vec2 q = bounds.frame.toLocal(x);
      bounds.low = {std::min(bounds.low.x, q.x), std::min(bounds.low.y, q.y)};
      bounds.high = {std::max(bounds.high.x, q.x), std::max(bounds.high.y, q.y)};
    }
  const std::array<Vec3, 4> corners{
      bounds.frame.toWorld(bounds.low), bounds.frame.toWorld({bounds.high.x, bounds.low.y}),
      bounds.frame.toWorld(bounds.high), bounds.frame.toWorld({bounds.low.x, bounds.high.y})};
  const Vec3 centre = bounds.frame.toWorld((bounds.low + bounds.high) * 0.5);
  for (int i = 0; i < 4; ++i) {
    Vec3 m = cross(corners[i] - apex, corners[(i + 1) % 4] - apex);
    const double size = length(m);
    // A point (nearly) in the light's plane or a flat rectangle has no cone worth testing: then
    // every feature is kept.
    if (!(size > 1e-300) || !std::isfinite(size)) return bounds;
    m = m / size;
    if (dot(m, centre - apex) > 0) m = -m;
    bounds.sides[i] = Plane{m, dot(m, apex)};
  }
  bounds.hasCone = true;
  return bounds;
}

}  // namespace

BackprojectionBuilder::BackprojectionBuilder(const PosedScene& scene,
                                             const ExactReference& reference)
    : scene_(scene), reference_(reference) {}

Backprojection BackprojectionBuilder::compute(PolygonId lightId, const Vec3& p, const Vec3& n,
                                              std::optional<PolygonId> receiver) const {
  return labelRegion(reference_.visibleLight(p, n, lightId, receiver), p, n);
}

Backprojection BackprojectionBuilder::compute(PolygonId lightId, const Vec3& p, const Vec3& n,
                                              std::optional<PolygonId> receiver,
                                              std::vector<PolygonId>& occluders) const {
  VisibleLight visible = reference_.visibleLight(p, n, lightId, receiver);
  Backprojection result = labelRegion(visible, p, n);
  occluders = std::move(visible.occluders);
  return result;
}

Backprojection BackprojectionBuilder::computeAmong(PolygonId lightId, const Vec3& p, const Vec3& n,
                                                   std::optional<PolygonId> receiver,
                                                   const std::vector<PolygonId>& candidates,
                                                   std::vector<PolygonId>& occluders) const {
  const WorldPolygon& light = scene_.polygons[lightId];
  VisibleLight visible =
      reference_.visiblePart(p, n, light.vertices, light.plane, lightId, candidates, receiver);
  Backprojection result = labelRegion(visible, p, n);
  occluders = std::move(visible.occluders);
  return result;
}

Backprojection BackprojectionBuilder::labelRegion(const VisibleLight& visible, const Vec3& p,
                                                  const Vec3& n) const {
  const PolygonId lightId = visible.light;
  Backprojection result;
  result.light = lightId;
  if (visible.rings.empty()) return result;

  const WorldPolygon& light = scene_.polygons[lightId];
  const Polygon3& lv = light.vertices;
  const double tolerance = 1e-9 * diameter(lv);
  const double coplanar = 1e-12 * scene_.extent.diagonalLength();
  const double pointHeight = light.plane.signedDistance(p);
  bool clippedByHorizon = false;
  for (const Vec3& v : lv) clippedByHorizon = clippedByHorizon || dot(n, v - p) < 0;

  // Only features that pass near a ring vertex can label it, and a polygon of many vertices (a
  // finely tessellated disc) crosses the cone from p in a few of them: features are kept only
  // within reach of the cone from p over the rings' bounding rectangle, so that labelling costs
  // little more per feature than this test. The test is conservative (below), so the labels are
  // those that testing every feature would give.
  const RingBounds bounds = ringBoundsOf(visible.rings, light.plane, p, 2 * tolerance + coplanar);

  // Candidate occluder features: the edges (a shared edge is one line, listed once) and vertices
  // of the polygons that entered the visible region's boolean operation.
  std::vector<Segment> edges;
  std::vector<std::pair<Vec3, FeatureRef>> projectedVertices;
  for (PolygonId id : visible.occluders) {
    const WorldPolygon& q = scene_.polygons[id];
    const size_t k = q.vertices.size();
    const auto visit = [&](size_t c) {  // the edge from corner c, and corner c
      const Vec3& a = q.vertices[c];
      const Vec3& b = q.vertices[c + 1 == k ? 0 : c + 1];
      const unsigned maskA = bounds.outsideMask(a);
      if ((maskA & bounds.outsideMask(b)) == 0) {
        // An edge in the horizon plane projects onto the horizon line: the horizon labels it.
        const bool inHorizon =
            std::abs(dot(n, a - p)) <= coplanar && std::abs(dot(n, b - p)) <= coplanar;
        if (!inHorizon) edges.push_back({a, b, {id, int(c)}});
      }
      // A vertex beyond a side plane by more than the margin and in front of p projects beyond
      // the rectangle's edge by more (central projection from p onto the light plane magnifies
      // distances to planes through p by 1/s ≥ 1).
      if (maskA != 0) return;
      const double drop = pointHeight - light.plane.signedDistance(a);
      if (drop > 0 && light.plane.signedDistance(a) > 0) {
        const Vec3 projected = p + (a - p) * (pointHeight / drop);
        if (bounds.holds(projected)) projectedVertices.push_back({projected, {id, int(c)}});
      }
    };
    if (q.edgeRuns.empty()) {
      for (size_t c = 0; c < k; ++c) visit(c);
      continue;
    }
    // Each run's box holds its edges' ends (edgeRuns), so a separated run has nothing to offer.
    for (const VertexRun& run : q.edgeRuns)
      if (!bounds.separates(run.box))
        for (size_t c = run.begin; c < run.end; ++c) visit(c);
  }

  withoutRepeatedEdges(edges);
  std::vector<size_t> byX(projectedVertices.size());
  for (size_t i = 0; i < byX.size(); ++i) byX[i] = i;
  std::sort(byX.begin(), byX.end(), [&](size_t i, size_t j) {
    return projectedVertices[i].first.x < projectedVertices[j].first.x;
  });

  for (const Polygon3& ring : visible.rings) {
    std::vector<BackprojectionVertex> cycle;
    for (const Vec3& x : ring) {
      BackprojectionVertex label;
      const auto lightCorner = std::find_if(
          lv.begin(), lv.end(), [&](const Vec3& v) { return distance(v, x) <= tolerance; });
      if (lightCorner != lv.end()) {
        label.kind = BackprojectionVertexKind::kLightVertex;
        label.lightFeature = int(lightCorner - lv.begin());
        cycle.push_back(label);
        continue;
      }
      // The first projected vertex (in visiting order) within tolerance: only those within it
      // along x can be, found in the order sorted by x.
      // (The window is wider than the tolerance by more than the rounding of these bounds.)
      const double reach = 2 * tolerance + 1e-15 * std::abs(x.x);
      size_t occluderCorner = projectedVertices.size();
      for (auto it = std::lower_bound(
               byX.begin(), byX.end(), x.x - reach,
               [&](size_t i, double v) { return projectedVertices[i].first.x < v; });
           it != byX.end() && projectedVertices[*it].first.x <= x.x + reach; ++it)
        if (*it < occluderCorner && distance(projectedVertices[*it].first, x) <= tolerance)
          occluderCorner = *it;
      if (occluderCorner != projectedVertices.size()) {
        label.kind = BackprojectionVertexKind::kOccluderVertex;
        label.first = projectedVertices[occluderCorner].second;
        cycle.push_back(label);
        continue;
      }
      std::vector<LineHit> lines;
      for (size_t i = 0; i < lv.size(); ++i)
        if (distanceToSegment(x, lv[i], lv[(i + 1) % lv.size()]) <= tolerance)
          lines.push_back({LineKind::kLightEdge, int(i), {}});
      if (clippedByHorizon && std::abs(dot(n, x - p)) <= tolerance)
        lines.push_back({LineKind::kHorizon, 0, {}});
      for (const Segment& e : edges)
        if (projectsThrough(p, x, e.a, e.b, tolerance))
          lines.push_back({LineKind::kOccluderEdge, 0, e.ref});
      if (lines.size() != 2) {  // degenerate here: more or fewer than two features meet
        result.isLabelled = false;
        return result;
      }
      const auto kinds = std::pair{lines[0].kind, lines[1].kind};
      const LineHit& first = lines[0];
      const LineHit& second = lines[1];
      using K = LineKind;
      if (kinds == std::pair{K::kLightEdge, K::kOccluderEdge}) {
        label = {
            BackprojectionVertexKind::kLightEdgeOccluderEdge, first.lightEdge, second.edge, {}};
      } else if (kinds == std::pair{K::kOccluderEdge, K::kOccluderEdge}) {
        label = {BackprojectionVertexKind::kOccluderEdgeOccluderEdge, 0, first.edge, second.edge};
      } else if (kinds == std::pair{K::kLightEdge, K::kHorizon}) {
        label = {BackprojectionVertexKind::kLightEdgeHorizon, first.lightEdge, {}, {}};
      } else if (kinds == std::pair{K::kHorizon, K::kOccluderEdge}) {
        label = {BackprojectionVertexKind::kOccluderEdgeHorizon, 0, second.edge, {}};
      } else {
        result.isLabelled = false;
        return result;
      }
      cycle.push_back(label);
    }
    result.cycles.push_back(std::move(cycle));
  }
  return result;
}

bool sameLabels(const Backprojection& a, const Backprojection& b, const EdgeAdjacency& adjacency) {
  // A feature is named through one of its polygons; an edge shared by two polygons (or a vertex
  // shared by several) may be named through either. Compare scene edges and vertices instead.
  const auto vertexOf = [&](const FeatureRef& f) {
    return adjacency.polygonVertices(f.polygon)[f.corner];
  };
  const auto edgeOf = [&](const FeatureRef& f) {
    const std::vector<VertexId>& corners = adjacency.polygonVertices(f.polygon);
    return adjacency.edgeBetween(corners[f.corner], corners[(f.corner + 1) % corners.size()]);
  };
  const auto flat = [&](const Backprojection& bp) {
    std::vector<std::array<int, 4>> labels;
    for (const auto& cycle : bp.cycles)
      for (const BackprojectionVertex& v : cycle) {
        std::array<int, 4> label{int(v.kind), v.lightFeature, -1, -1};
        switch (v.kind) {
          case BackprojectionVertexKind::kLightVertex:
          case BackprojectionVertexKind::kLightEdgeHorizon:
            break;
          case BackprojectionVertexKind::kOccluderVertex:
            label[2] = vertexOf(v.first);
            break;
          case BackprojectionVertexKind::kOccluderEdgeOccluderEdge:
            label[2] = edgeOf(v.first);
            label[3] = edgeOf(v.second);
            if (label[3] < label[2]) std::swap(label[2], label[3]);
            break;
          case BackprojectionVertexKind::kLightEdgeOccluderEdge:
          case BackprojectionVertexKind::kOccluderEdgeHorizon:
            label[2] = edgeOf(v.first);
            break;
        }
        labels.push_back(label);
      }
    // Sets, not multisets: a degenerate region (a vertex doubled where two features pass through
    // one point) names the same features.
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    return labels;
  };
  return a.light == b.light && flat(a) == flat(b);
}

std::vector<Polygon3> BackprojectionBuilder::evaluate(const Backprojection& bp, const Vec3& q,
                                                      const Vec3& n,
                                                      std::optional<PolygonId> receiver) const {
  if (!bp.isLabelled) return reference_.visibleLight(q, n, bp.light, receiver).rings;
  const WorldPolygon& light = scene_.polygons[bp.light];
  const Polygon3& lv = light.vertices;
  const Plane& lp = light.plane;
  const double height = lp.signedDistance(q);
  std::vector<Polygon3> rings;
  if (height <= 0) return rings;
  const auto edge = [&](const FeatureRef& f) {
    const Polygon3& v = scene_.polygons[f.polygon].vertices;
    return std::pair{v[f.corner], v[(f.corner + 1) % v.size()]};
  };
  // The plane through q and an occluder edge: its trace on the light plane is the edge's shadow
  // line.
  const auto edgePlane = [&](const FeatureRef& f) {
    const auto [a, b] = edge(f);
    const Vec3 m = cross(a - q, b - q);
    return std::pair{m, dot(m, q)};
  };
  const double horizonOffset = dot(n, q);
  for (const auto& cycle : bp.cycles) {
    Polygon3 ring;
    for (const BackprojectionVertex& v : cycle) {
      const Vec3& c = lv[v.lightFeature];
      const Vec3& d = lv[(v.lightFeature + 1) % lv.size()];
      switch (v.kind) {
        case BackprojectionVertexKind::kLightVertex:
          ring.push_back(c);
          break;
        case BackprojectionVertexKind::kLightEdgeHorizon:
          ring.push_back(linePlane(c, d, n, horizonOffset));
          break;
        case BackprojectionVertexKind::kLightEdgeOccluderEdge: {
          const auto [m, off] = edgePlane(v.first);
          ring.push_back(linePlane(c, d, m, off));
          break;
        }
        case BackprojectionVertexKind::kOccluderVertex: {
          const Vec3& a = scene_.polygons[v.first.polygon].vertices[v.first.corner];
          ring.push_back(q + (a - q) * (height / (height - lp.signedDistance(a))));
          break;
        }
        case BackprojectionVertexKind::kOccluderEdgeOccluderEdge: {
          const auto [m1, o1] = edgePlane(v.first);
          const auto [m2, o2] = edgePlane(v.second);
          ring.push_back(intersectThreePlanes(lp.normal, lp.offset, m1, o1, m2, o2));
          break;
        }
        case BackprojectionVertexKind::kOccluderEdgeHorizon: {
          const auto [m, off] = edgePlane(v.first);
          ring.push_back(intersectThreePlanes(lp.normal, lp.offset, m, off, n, horizonOffset));
          break;
        }
      }
    }
    rings.push_back(std::move(ring));
  }
  return rings;
}

Rgb BackprojectionBuilder::irradiance(const std::vector<Backprojection>& perLight, const Vec3& q,
                                      const Vec3& n, std::optional<PolygonId> receiver) const {
  Rgb total;
  for (const Backprojection& bp : perLight) {
    double formFactor = 0;
    for (const Polygon3& ring : evaluate(bp, q, n, receiver))
      formFactor += pointToPolygonFormFactor(q, n, ring);
    total += scene_.materialOf(scene_.polygons[bp.light]).emission * formFactor;
  }
  return total;
}

}  // namespace penumbra
