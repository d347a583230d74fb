// Link estimates: form factor, its variation over the receiver, and visibility.
//
// Element to element: the transfer is the receiver-area mean of the exact point-to-polygon form
// factor (Lambert's formula on the source clipped to the receiver point's front half-space),
// integrated by an adaptive midpoint rule on the receiver's quadtree (at least its 16
// grandchildren; cells are split further while their four children's mean disagrees with their
// centre value, as near an edge shared with the source, where the point form factor is steep).
// Exact per point, so the form factors of the sources seen from a point sum to 1 in a closed scene,
// up to visibility; visibility is the fraction of unoccluded rays between stratified points.
// Two elements in contact face to face (coplanar, opposite normals: a box standing on the floor,
// a door glued on a cabinet) see only each other where they overlap: the limit of the form factor
// as the gap closes is the overlap's share of the receiver's area, with nothing in between.
//
// A cluster at one end (Smits, Arvo & Greenberg 1994; Sillion 1995): receiver points area-uniform
// and stratified over the receiver's surfaces; at each, the exact unoccluded form factor to every
// root element of the source (Lambert's formula, no singularity, no regularisation bias), and one
// ray to a point of a source element chosen in proportion to its form factor, so the visibility is
// form-factor weighted. The transfer is the mean over the receiver points.

#include "penumbra/radiosity/radiosity_solver.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <numeric>
#include <optional>
#include <utility>
#include <vector>

#include "penumbra/base/split_mix.h"
#include "penumbra/geometry/spherical_triangle.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/radiosity/point_form_factor.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

namespace {

std::uint64_t linkSeed(std::uint64_t seed, NodeRef r, NodeRef s) {
  SplitMix mix(seed ^ (std::uint64_t(r.index) << 1 | r.kind) * 0x100000001b3ull ^
               (std::uint64_t(s.index) << 33 | std::uint64_t(s.kind) << 32));
  mix.next();
  return mix.next();
}

Polygon3 loopOf(const Element& e) {
  return Polygon3(e.vertices.begin(), e.vertices.begin() + e.vertexCount);
}

// Relative slack for "on the plane": a polygon touching a plane counts as lying in it.
double contactSlack(const PosedScene& scene) {
  return 1e-9 * std::max(1.0, scene.extent.diagonalLength());
}

Vec3 vertexMean(const std::array<Vec3, 4>& loop, int count) {
  Vec3 c{0, 0, 0};
  for (int i = 0; i < count; ++i) c += loop[i];
  return c / double(count);
}

// The share of r's area that the element s covers when both lie in one plane facing each other,
// or nothing when they do not (both are convex: r is clipped by the inner half-spaces of s's
// edges).
std::optional<double> contactShare(const Element& r, const Element& s, double slack) {
  if (dot(r.normal, s.normal) > -1 + 1e-9) return std::nullopt;
  const Plane plane = Plane::fromPointNormal(s.vertices[0], s.normal);
  for (int i = 0; i < r.vertexCount; ++i)
    if (std::abs(plane.signedDistance(r.vertices[i])) > slack) return std::nullopt;
  Polygon3 overlap = loopOf(r);
  for (int i = 0; i < s.vertexCount && overlap.size() >= 3; ++i) {
    const Vec3& a = s.vertices[i];
    const Vec3& b = s.vertices[(i + 1) % s.vertexCount];
    overlap = clipByPlane(overlap, Plane::fromPointNormal(a, cross(s.normal, b - a)));
  }
  return overlap.size() >= 3 ? std::min(1.0, area(overlap) / r.area) : 0.0;
}

// The quadrature's deepest levels (see FormFactorQuadrature::maxLevel).
constexpr int kLinkMaxLevel = 1;
constexpr int kCellMaxLevel = 6;

// Adaptive midpoint rule for the mean over the cell `loop` of the point form factor to `s`.
// `centre` is the value at the cell's centre; `level` counts cells below the receiver.
struct FormFactorQuadrature {
  const Element& source;
  Vec3 normal;
  int vertexCount;
  double lowest = 1e300, highest = 0;
  int evaluations = 0;
  // When set, the values at the receiver's 16 grandchild centres (level 1 of the recursion
  // always evaluates them, in Element::grandchildCentres order): the receiver oracle needs them.
  std::array<float, 16>* grandchildValues = nullptr;

  static constexpr int kMinLevel = 1;  // grandchildren of the receiver at least (16 points)
  // The deepest level: 6 (1/64 of the receiver's side) where the mean itself is the answer (the
  // final gather's cells next to a source); 1 for links, whose estimate only steers refinement
  // (what is shown is the final gather's), so 16 points carry all they need (measured on the
  // Cornell box: the same median and p95 error at 1e-3 and 3e-4, links estimated 2x faster).
  int maxLevel = kLinkMaxLevel;
  static constexpr double kAbsoluteTolerance = 1e-4;

  double at(const Vec3& x) {
    ++evaluations;
    const double f = pointToElementFormFactor(x, normal, source);
    lowest = std::min(lowest, f);
    highest = std::max(highest, f);
    return f;
  }
  double mean(const std::array<Vec3, 4>& loop, double centre, int level, int quadrant = 0) {
    Element cell;
    cell.vertices = loop;
    cell.vertexCount = std::uint8_t(vertexCount);
    const auto children = cell.childVertices();
    std::array<double, 4> values{}, areas{};
    double sum = 0, total = 0;
    for (int k = 0; k < 4; ++k) {
      areas[k] = elementArea(children[k], vertexCount);
      values[k] = at(vertexMean(children[k], vertexCount));
      sum += areas[k] * values[k];
      total += areas[k];
    }
    if (level == 1 && grandchildValues)
      for (int k = 0; k < 4; ++k) (*grandchildValues)[4 * quadrant + k] = float(values[k]);
    // A sliver whose children's areas round to nothing (a receiver cut by the source's plane
    // within rounding of a vertex): its centre value is all there is.
    if (!(total > 0)) return centre;
    const double estimate = sum / total;
    if (level >= maxLevel ||
        (level >= kMinLevel && std::abs(estimate - centre) <= kAbsoluteTolerance))
      return estimate;
    sum = 0;
    for (int k = 0; k < 4; ++k) sum += areas[k] * mean(children[k], values[k], level + 1, k);
    return sum / total;
  }
};

// The part of the receiver in front of the source's plane, as triangles (a fan): the form factor
// is 0 behind that plane.
std::vector<std::array<Vec3, 4>> frontTriangles(const Element& receiver, const Element& source) {
  const Polygon3 front =
      clipByPlane(loopOf(receiver), Plane::fromPointNormal(source.vertices[0], source.normal));
  std::vector<std::array<Vec3, 4>> triangles;
  for (size_t t = 1; t + 1 < front.size(); ++t)
    if (const std::array<Vec3, 4> triangle{front[0], front[t], front[t + 1], Vec3{}};
        elementArea(triangle, 3) > 0)
      triangles.push_back(triangle);
  return triangles;
}

// Does the source's plane cut the receiver (some of it in front, some behind)?
bool straddles(const Element& receiver, const Element& source) {
  const Plane plane = Plane::fromPointNormal(source.vertices[0], source.normal);
  int behind = 0;
  for (int i = 0; i < receiver.vertexCount; ++i)
    behind += plane.signedDistance(receiver.vertices[i]) <= 0 ? 1 : 0;
  return behind > 0 && behind < receiver.vertexCount;
}

struct ReceiverQuadrature {
  double mean = 0, lowest = 0, highest = 0;
};

// The receiver-area mean of the point form factor to the source. Where the source's plane cuts
// the receiver (a floor element under the side of a box standing on it), the quadrature runs
// over the part in front only: on the whole receiver its points could all fall behind and miss a
// strip in front, where the box's side fills a third of the hemisphere (such links were dropped
// as empty, and floor leaves along boxes had 70% of their furnace irradiance).
ReceiverQuadrature meanFormFactor(const Element& re, const Element& se, int maxLevel,
                                  std::array<float, 16>* grandchildValues = nullptr) {
  ReceiverQuadrature result;
  if (!straddles(re, se)) {
    FormFactorQuadrature quadrature{se, re.normal, re.vertexCount};
    quadrature.maxLevel = maxLevel;
    quadrature.grandchildValues = grandchildValues;
    result.mean = quadrature.mean(re.vertices, quadrature.at(re.centroid()), 0);
    result.lowest = quadrature.lowest;
    result.highest = quadrature.highest;
    return result;
  }
  double sum = 0;
  for (const auto& triangle : frontTriangles(re, se)) {
    FormFactorQuadrature quadrature{se, re.normal, 3};
    quadrature.maxLevel = maxLevel;
    sum += elementArea(triangle, 3) *
           quadrature.mean(triangle, quadrature.at(vertexMean(triangle, 3)), 0);
    result.highest = std::max(result.highest, quadrature.highest);
  }
  result.mean = sum / re.area;  // lowest stays 0: the part behind receives nothing
  return result;
}

// A point of element e seen from x (normal n), uniform in the solid angle of the part of e in
// front of x (so the parts of a large source near x are sampled as much as they matter), or
// uniform in area when that part is degenerate seen from x.
Vec3 sampleSeenFrom(const Vec3& x, const Vec3& n, const Element& e, double u1, double u2) {
  const Polygon3 front = clipByPlane(loopOf(e), Plane::fromPointNormal(x, n));
  const int triangles = int(front.size()) - 2;
  if (triangles >= 1) {
    std::array<double, 8> omega{};
    double total = 0;
    const int count = std::min(triangles, int(omega.size()));
    for (int t = 0; t < count; ++t) {
      sampleSphericalTriangle(x, front[0], front[t + 1], front[t + 2], 0, 0, &omega[t]);
      if (!(omega[t] > 0) || !std::isfinite(omega[t])) omega[t] = 0;
      total += omega[t];
    }
    if (total > 1e-12) {
      double w = u1 * total;
      int t = 0;
      while (t + 1 < count && w >= omega[t]) w -= omega[t++];
      const double v1 = std::clamp(w / std::max(omega[t], 1e-300), 0.0, 1.0 - 1e-12);
      if (const auto d = sampleSphericalTriangle(x, front[0], front[t + 1], front[t + 2], v1, u2)) {
        const double denominator = dot(e.normal, *d);
        if (denominator < 0) {
          const Vec3 y = x + *d * (dot(e.normal, e.vertices[0] - x) / denominator);
          if (std::isfinite(y.x) && std::isfinite(y.y) && std::isfinite(y.z)) return y;
        }
      }
    }
  }
  return e.samplePoint(u1, u2);
}

// Largest minus smallest form factor from the source's 16 grandchild centres to the receiver.
double sourceSideSpread(const Element& source, const Element& receiver) {
  double lowest = 1e300, highest = 0;
  for (const auto& loop : source.childVertices()) {
    Element child;
    child.vertices = loop;
    child.vertexCount = source.vertexCount;
    for (const auto& subLoop : child.childVertices()) {
      const double f = pointToElementFormFactor(vertexMean(subLoop, source.vertexCount),
                                                source.normal, receiver);
      lowest = std::min(lowest, f);
      highest = std::max(highest, f);
    }
  }
  return highest - lowest;
}

}  // namespace

void RadiositySolver::estimate(Link& link, EstimateCounters& counters, PointTransfers* pointValues,
                               std::optional<Shaft>* shaft) const {
  SplitMix rng(linkSeed(options_.seed, link.receiver, link.source));
  const NodeRef r = link.receiver, s = link.source;
  if (!r.isCluster() && !s.isCluster()) {
    const Element& re = elements_[r.index];
    const Element& se = elements_[s.index];
    if (const auto share = contactShare(re, se, contactSlack(scene_))) {
      link.unoccludedTransfer = float(*share);
      link.transferSpread = *share > 0 && *share < 1 ? 1.f : 0.f;
      link.visibility = *share > 0 ? 1.f : 0.f;
      return;
    }
    std::array<float, 16> grandchildValues{};
    grandchildValues.fill(-1);
    const ReceiverQuadrature quadrature = meanFormFactor(re, se, kLinkMaxLevel, &grandchildValues);
    if (pointValues && grandchildValues[0] >= 0) {
      pointValues->values = grandchildValues;
      pointValues->valid = true;
      pointValues->unoccluded = true;
    }
    link.unoccludedTransfer = float(quadrature.mean);
    link.transferSpread = float(quadrature.highest - quadrature.lowest);
    link.sourceSpread = float(sourceSideSpread(se, re));
    if (link.unoccludedTransfer <= 0) {
      link.visibility = 0;
      return;
    }
    if (options_.exactVisibility && !options_.elementSourceShares &&
        link.unoccludedTransfer >= options_.exactVisibilityMinTransfer) {
      estimateExactVisibility(link, re, se, counters);
      return;
    }
    // Nothing in the link's shaft and no polygon in contact with either end: every ray would
    // pass, so the link is wholly visible, exactly and without casting them.
    if (!options_.elementSourceShares && contacts_[re.polygon].empty() &&
        contacts_[se.polygon].empty() && [&] {
          std::optional<Shaft> built;
          std::optional<Shaft>& used = shaft ? *shaft : built;
          if (!used) used.emplace(loopOf(re), loopOf(se));
          return shaftOccluders(*used, re.polygon, se.polygon).empty();
        }()) {
      link.visibility = 1;
      ++counters.unoccludedByShaft;
      return;
    }
    // Stratified jittered points on both ends, the source strata shuffled against the receiver's.
    const int n = std::max(1, options_.visibilityRays);
    const int side = std::max(1, int(std::lround(std::sqrt(double(n)))));
    std::vector<int> order(n);
    for (int i = 0; i < n; ++i) order[i] = i;
    for (int i = n - 1; i > 0; --i) std::swap(order[i], order[rng.next() % (i + 1)]);
    double weightSum = 0, visibleWeight = 0;
    // Where on the source the visible transfer lands, by the source's sixteen grandchildren
    // (quadtree cells two levels down, whether or not it is split yet): see Link::sourceShares.
    std::array<Element, 16> cells{};
    {
      Element quadrant;
      quadrant.vertexCount = se.vertexCount;
      quadrant.normal = se.normal;
      int k = 0;
      for (const auto& loop : se.childVertices()) {
        quadrant.vertices = loop;
        for (const auto& subLoop : quadrant.childVertices()) {
          cells[k].vertices = subLoop;
          cells[k].vertexCount = se.vertexCount;
          cells[k].normal = se.normal;
          ++k;
        }
      }
    }
    std::array<double, 16> landed{};
    for (int i = 0; i < n; ++i) {
      const auto stratum = [&](int k, double& u, double& v) {
        const int cell = k % (side * side);
        u = (cell % side + rng.uniform()) / side;
        v = (cell / side + rng.uniform()) / side;
      };
      double u, v;
      stratum(i, u, v);
      const Vec3 x = re.samplePoint(u, v);
      stratum(order[i], u, v);
      // y uniform in the solid angle of the source seen from x, and x weighted by its form
      // factor to the source: the visible fraction of the transfer, not of the pairs of points
      // (uniform pairs undersample the parts of the source that matter most, nearby ones).
      const Vec3 y = sampleSeenFrom(x, re.normal, se, u, v);
      const double weight = pointToElementFormFactor(x, re.normal, se);
      weightSum += weight;
      if (isVisible(re.polygon, x, se.polygon, y)) {
        visibleWeight += weight;
        if (!options_.elementSourceShares) continue;
        int cell = 0;
        double inside = cells[0].insideness(y);
        for (int k = 1; k < 16; ++k)
          if (const double d = cells[k].insideness(y); d > inside) cell = k, inside = d;
        landed[cell] += weight;
      }
    }
    counters.visibilityRays += n;
    link.visibility = weightSum > 0 ? float(visibleWeight / weightSum) : 0.f;
    link.sourceShares.clear();
    if (const double total = std::accumulate(landed.begin(), landed.end(), 0.0);
        options_.elementSourceShares && total > 0)
      for (double w : landed) link.sourceShares.push_back(float(w / total));
    return;
  }
  // A cluster at one end or both: exact point-to-element form factors from receiver points to
  // the source's root elements (or the source element), one form-factor-weighted ray per point.
  std::vector<int> sources;
  if (s.isCluster())
    sources.assign(rootOrder_.begin() + clusters_[s.index].elementBegin,
                   rootOrder_.begin() + clusters_[s.index].elementEnd);
  else
    sources.push_back(s.index);
  std::vector<double> cumulative(sources.size() + 1, 0);
  std::vector<double> shares(s.isCluster() ? sources.size() : 0, 0.0);
  const int n = std::max(1, options_.clusterSamples);
  double unoccluded = 0, visible = 0, lowest = 1e300, highest = 0;
  for (int i = 0; i < n; ++i) {
    // Drawn in sequence (function arguments are not): the cluster's share, then v, then u.
    const double w = (i + rng.uniform()) / n, v = rng.uniform(), u = rng.uniform();
    const SurfacePoint x = samplePoint(r, u, v, w);
    for (size_t k = 0; k < sources.size(); ++k)
      cumulative[k + 1] =
          cumulative[k] + pointToElementFormFactor(x.position, x.normal, elements_[sources[k]]);
    const double f = cumulative.back();
    for (size_t k = 0; k < shares.size(); ++k) shares[k] += cumulative[k + 1] - cumulative[k];
    lowest = std::min(lowest, f);
    highest = std::max(highest, f);
    if (!(f > 0)) continue;
    unoccluded += f;
    const double target = rng.uniform() * f;
    const size_t k = std::min<size_t>(
        std::upper_bound(cumulative.begin() + 1, cumulative.end(), target) - cumulative.begin() - 1,
        sources.size() - 1);
    const double second = rng.uniform(), first = rng.uniform();  // in sequence, as above
    const Vec3 y = sampleSeenFrom(x.position, x.normal, elements_[sources[k]], first, second);
    ++counters.visibilityRays;
    if (isVisible(x.polygon, x.position, elements_[sources[k]].polygon, y)) visible += f;
  }
  link.unoccludedTransfer = float(unoccluded / n);
  link.sourceShares.clear();
  if (unoccluded > 0)
    for (double share : shares) link.sourceShares.push_back(float(share / unoccluded));
  // The variation over the receiver's points, or the whole transfer when the receiver is a
  // cluster (its surfaces face different ways: gathering gives them all the mean).
  link.transferSpread = r.isCluster() ? link.unoccludedTransfer : float(highest - lowest);
  link.visibility = unoccluded > 0 ? float(visible / unoccluded) : 0.f;
  link.sourceSpread = float(link.unoccludedTransfer * area(r) / area(s));
}

std::vector<PolygonId> RadiositySolver::shaftOccluders(const Element& receiver,
                                                       const Element& source) const {
  return shaftOccluders(Shaft(loopOf(receiver), loopOf(source)), receiver.polygon, source.polygon);
}

std::vector<PolygonId> RadiositySolver::shaftOccluders(const Shaft& shaft, PolygonId receiver,
                                                       PolygonId source) const {
  std::vector<PolygonId> occluders;
  grid_->forEachCellOverlappingBox(shaft.hull(), [&](int cell) {
    if (!shaft.mayIntersect(grid_->cellBounds(cell))) return;
    for (PolygonId id : grid_->polygonsInCell(cell))
      if (id != receiver && id != source && shaft.mayIntersect(scene_.polygons[id].bounds))
        occluders.push_back(id);
  });
  std::sort(occluders.begin(), occluders.end());
  occluders.erase(std::unique(occluders.begin(), occluders.end()), occluders.end());
  return occluders;
}

double RadiositySolver::visibleTransfer(const Vec3& x, const Vec3& normal, PolygonId receiver,
                                        const Element& source, std::span<const PolygonId> occluders,
                                        double unoccluded, long long& clippedPoints) const {
  constexpr double kWhollyVisible = 1e-9;
  if (occluders.empty()) return unoccluded;
  ++clippedPoints;
  const double v = visibleParts_->visibleFormFactor(
      x, normal, loopOf(source), Plane::fromPointNormal(source.vertices[0], source.normal),
      source.polygon, occluders, receiver);
  // The clipped region's vertices are rounded to a 2^-60 grid of the source: a wholly visible
  // source must read as wholly visible (the link oracle refines partial ones).
  if (v > unoccluded * (1 - kWhollyVisible)) return unoccluded;
  if (v < unoccluded * kWhollyVisible) return 0;
  return v;
}

// Visibility as the ratio of the visible to the unoccluded form factor summed over the receiver's
// 16 grandchild centres, each visible form factor exact (the source clipped by the projections of
// the shaft's polygons from that point). No noise: a closed scene's visible form factors from a
// point sum to 1, which the rays' estimate only did on average.
void RadiositySolver::estimateExactVisibility(Link& link, const Element& re, const Element& se,
                                              EstimateCounters& counters) const {
  link.pointVisibleTransfers.clear();
  const std::vector<PolygonId> occluders = shaftOccluders(re, se);
  if (occluders.empty() && contacts_[re.polygon].empty()) {
    link.visibility = 1;
    return;
  }
  // The form factor and exact visible form factor at x.
  const auto atPoint = [&](const Vec3& x) -> std::pair<double, double> {
    const double f = pointToElementFormFactor(x, re.normal, se);
    if (!(f > 0) || isCovered(re.polygon, x)) return {f, 0.0};
    return {f, visibleTransfer(x, re.normal, re.polygon, se, occluders, f,
                               counters.exactVisibilityPoints)};
  };
  double unoccluded = 0, visible = 0;
  link.pointVisibleTransfers.resize(16);
  const std::array<Vec3, 16> points = re.grandchildCentres();
  for (int k = 0; k < 16; ++k) {
    const auto [f, v] = atPoint(points[k]);
    unoccluded += f;
    visible += v;
    link.pointVisibleTransfers[k] = float(v);
  }
  // A receiver cut by the source's plane: the ratio over its front part (the grandchild centres
  // may all lie behind it), at the grandchild centres of the front's triangles, by area.
  if (straddles(re, se)) {
    unoccluded = visible = 0;
    for (const auto& triangle : frontTriangles(re, se)) {
      Element cell;
      cell.vertices = triangle;
      cell.vertexCount = 3;
      const double weight = elementArea(triangle, 3);
      for (const Vec3& x : cell.grandchildCentres()) {
        const auto [f, v] = atPoint(x);
        unoccluded += weight * f;
        visible += weight * v;
      }
    }
  }
  link.visibility = unoccluded > 0 ? float(visible / unoccluded) : 0.f;
  // Wholly visible or wholly hidden: the receiver oracle's F(x) × visibility is then exact.
  if (link.visibility == 1 || link.visibility == 0) link.pointVisibleTransfers.clear();
}

}  // namespace penumbra

namespace penumbra {

// The link's unoccluded transfer seen from one point of its receiver: the exact point form factor
// to a source element (to the root elements of a source cluster).
double RadiositySolver::unoccludedPointTransfer(const Link& link, const Vec3& x, const Vec3& normal,
                                                bool covered) const {
  const NodeRef s = link.source;
  double f = 0;
  if (!s.isCluster()) {
    const Element& se = elements_[s.index];
    if (!link.receiver.isCluster() &&
        contactShare(elements_[link.receiver.index], se, contactSlack(scene_)))
      return se.insideness(x) >= 0 ? 1 : 0;  // in contact: the source covers x or not
    if (covered) return 0;                   // x sees only what covers it
    f = pointToElementFormFactor(x, normal, se);
  } else {
    if (covered) return 0;
    const Cluster& c = clusters_[s.index];
    for (int i = c.elementBegin; i < c.elementEnd; ++i)
      f += pointToElementFormFactor(x, normal, elements_[rootOrder_[i]]);
  }
  return f;
}

double RadiositySolver::pointFormFactor(const Vec3& x, const Vec3& normal, const Element& e) const {
  return pointToElementFormFactor(x, normal, e);
}

double RadiositySolver::cellFormFactor(const std::array<Vec3, 4>& cell, const Element& receiver,
                                       const Element& source) const {
  Element c;
  c.vertices = cell;
  c.vertexCount = receiver.vertexCount;
  c.normal = receiver.normal;
  c.area = elementArea(cell, receiver.vertexCount);
  if (!(c.area > 0)) return pointToElementFormFactor(c.centroid(), receiver.normal, source);
  return meanFormFactor(c, source, kCellMaxLevel).mean;
}

double RadiositySolver::pointTransfer(const Link& link, const Vec3& x, const Vec3& normal,
                                      bool covered) const {
  return unoccludedPointTransfer(link, x, normal, covered) * link.visibility;
}

}  // namespace penumbra
