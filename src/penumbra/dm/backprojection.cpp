#include "penumbra/dm/backprojection.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

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

double distanceToSegment(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp(dot(x - a, ab) / dot(ab, ab), 0.0, 1.0);
  return distance(x, a + ab * t);
}

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

}  // namespace

BackprojectionBuilder::BackprojectionBuilder(const PosedScene& scene, const UniformGrid& grid,
                                             const ExactReference& reference)
    : scene_(scene), grid_(grid), reference_(reference) {}

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

  // Candidate occluder features: the edges (a shared edge is one line, listed once) and vertices
  // of the polygons that entered the visible region's boolean operation.
  std::vector<Segment> edges;
  std::vector<std::pair<Vec3, FeatureRef>> projectedVertices;
  std::set<std::pair<std::array<double, 3>, std::array<double, 3>>> seenEdges;
  const auto key = [](const Vec3& v) { return std::array<double, 3>{v.x, v.y, v.z}; };
  for (PolygonId id : visible.occluders) {
    const WorldPolygon& q = scene_.polygons[id];
    const size_t k = q.vertices.size();
    for (size_t c = 0; c < k; ++c) {
      const Vec3& a = q.vertices[c];
      const Vec3& b = q.vertices[(c + 1) % k];
      // An edge in the horizon plane projects onto the horizon line: the horizon labels it.
      const bool inHorizon =
          std::abs(dot(n, a - p)) <= coplanar && std::abs(dot(n, b - p)) <= coplanar;
      const auto ends = key(a) < key(b) ? std::pair{key(a), key(b)} : std::pair{key(b), key(a)};
      if (!inHorizon && seenEdges.insert(ends).second) edges.push_back({a, b, {id, int(c)}});
      const double drop = pointHeight - light.plane.signedDistance(a);
      if (drop > 0 && light.plane.signedDistance(a) > 0)
        projectedVertices.push_back({p + (a - p) * (pointHeight / drop), {id, int(c)}});
    }
  }

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
      const auto occluderCorner =
          std::find_if(projectedVertices.begin(), projectedVertices.end(),
                       [&](const auto& v) { return distance(v.first, x) <= tolerance; });
      if (occluderCorner != projectedVertices.end()) {
        label.kind = BackprojectionVertexKind::kOccluderVertex;
        label.first = occluderCorner->second;
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
