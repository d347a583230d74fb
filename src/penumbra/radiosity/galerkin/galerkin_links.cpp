// Galerkin links: which node pairs can exchange light, their shafts' occluder candidates, and the
// cubature estimate of a link's coefficients with 0/1 visibility along each point pair.

#include <algorithm>
#include <cmath>
#include <numbers>

#include "penumbra/base/check.h"
#include "penumbra/geometry/polygon.h"
#include "penumbra/radiosity/galerkin/galerkin_internals.h"
#include "penumbra/radiosity/point_form_factor.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/shaft.h"

namespace penumbra {

namespace {

// The mean of max(0, cos θ) over all directions: a cluster end's cosine in the transfers the
// oracle weighs (its coefficients take the direction from the cluster's lobes instead).
constexpr double kClusterCosine = 0.25;

// Element ends nearer than this share of the larger one's size have their receiver's form factor
// sampled at its corners too (GalerkinRadiosity::estimate).
constexpr double kNearShare = 0.25;

// A receiver point farther from an element source's centre than this many times its size takes
// the cubature's form factor instead of the exact one (Lambert's formula, a sixth of a Cornell box
// solve): measured on the Cornell box and the chair rooms at 1e-2 ... 1e-4, the same links within
// 0.1%, the same median and 95th percentile errors within 0.04%, and absorbed/emitted within
// 0.0004.
constexpr double kFarSizes = 2;

// The points where a link samples one of its ends.
struct EndPoints {
  std::array<Vec3, 4> points{};
  std::array<double, 4> weights{};
  std::array<std::array<double, 3>, 4> basis{};  // φ at each point (a cluster: constant only)
  int count = 0;
  bool isCluster = false;
  Vec3 normal;  // an element's
  Box3 box;     // a cluster's
};

EndPoints elementPoints(const GalerkinRadiosity::GElement& e) {
  EndPoints end;
  end.count = e.cubature.count;
  end.points = e.cubature.points;
  end.weights = e.cubature.weights;
  end.basis = e.cubatureBasis;
  end.normal = e.shape.normal;
  return end;
}

// Four points of the box at the corners of a regular tetrahedron inscribed in the half-size
// box around its centre: fixed, so a link's estimate is the same whenever it is made.
EndPoints clusterPoints(const Box3& box) {
  EndPoints end;
  end.isCluster = true;
  end.box = box;
  end.count = 4;
  const Vec3 c = box.center(), h = box.diagonal() * 0.25;
  constexpr std::array<std::array<double, 3>, 4> kSigns{
      {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}}};
  for (int i = 0; i < 4; ++i) {
    end.points[i] = c + Vec3{h.x * kSigns[i][0], h.y * kSigns[i][1], h.z * kSigns[i][2]};
    end.weights[i] = 0.25;
    end.basis[i] = {1, 0, 0};
  }
  return end;
}

}  // namespace

bool GalerkinRadiosity::canExchange(NodeRef r, NodeRef s) const {
  if (r == s) return r.isCluster();
  if ((r.isElement() && elements_[r.index].cover == GElement::kCovered) ||
      (s.isElement() && elements_[s.index].cover == GElement::kCovered))
    return false;
  // Is all of node n behind (or in) the plane of element e?
  const auto behind = [&](const GElement& e, NodeRef n) {
    const Vec3& normal = e.shape.normal;
    const double offset = dot(normal, e.shape.vertices[0]);
    if (n.isElement()) {
      const ElementShape& shape = elements_[n.index].shape;
      for (int i = 0; i < shape.vertexCount; ++i)
        if (dot(normal, shape.vertices[i]) - offset > 0) return false;
      return true;
    }
    const Box3& box = clusters_[n.index].structure.bounds;
    const Vec3 farthest{normal.x > 0 ? box.max.x : box.min.x, normal.y > 0 ? box.max.y : box.min.y,
                        normal.z > 0 ? box.max.z : box.min.z};
    return dot(normal, farthest) - offset <= 0;
  };
  if (r.isElement() && s.isElement() && elements_[r.index].polygon == elements_[s.index].polygon)
    return false;
  if (r.isElement() && behind(elements_[r.index], s)) return false;
  if (s.isElement() && behind(elements_[s.index], r)) return false;
  return true;
}

std::vector<PolygonId> GalerkinRadiosity::shaftCandidates(
    NodeRef r, NodeRef s, const std::vector<PolygonId>& among) const {
  // Box-to-box shafts for every link: the polygon-to-polygon hull is tighter but cost a quarter
  // of the solve, and a segment is tested against each candidate's box before any ray anyway
  // (measured: the same rays, the same solution, 25% faster). Most deep pairs inherit no
  // candidates: no shaft to make.
  if (among.empty()) return {};
  return candidatesIn(Shaft(bounds(r), bounds(s)), r, s, among);
}

std::pair<PolygonId, PolygonId> GalerkinRadiosity::ownPolygons(NodeRef r, NodeRef s) const {
  return {r.isElement() ? elements_[r.index].polygon : PolygonId(-1),
          s.isElement() ? elements_[s.index].polygon : PolygonId(-1)};
}

std::vector<PolygonId> GalerkinRadiosity::candidatesIn(const Shaft& shaft, NodeRef r, NodeRef s,
                                                       const std::vector<PolygonId>& among,
                                                       const std::vector<char>* skip) const {
  const auto [ownR, ownS] = ownPolygons(r, s);
  std::vector<PolygonId> candidates;
  for (PolygonId id : among)
    if (id != ownR && id != ownS && !(skip && (*skip)[id]) &&
        shaft.mayIntersect(polygonBounds_[id]))
      candidates.push_back(id);
  return candidates;
}

GalerkinRadiosity::Estimate GalerkinRadiosity::estimate(NodeRef r, NodeRef s,
                                                        const CandidateView& candidates,
                                                        Counters& counters,
                                                        const VisibilityReuse* reuse) const {
  const EndPoints receiver = r.isCluster() ? clusterPoints(clusters_[r.index].structure.bounds)
                                           : elementPoints(elements_[r.index]);
  const EndPoints source = s.isCluster() ? clusterPoints(clusters_[s.index].structure.bounds)
                                         : elementPoints(elements_[s.index]);
  const double sourceArea = area(s);
  // Unit, from the receiver's centre to the source's: the direction a cluster end's lobes use.
  const Vec3 between = bounds(s).center() - bounds(r).center();
  const Vec3 direction = length(between) > 0 ? normalize(between) : Vec3{0, 0, 1};
  const bool mayBeHidden = candidates.count > 0;
  if (!mayBeHidden) ++counters.unoccludedLinks;
  // What the two ends alone give (kept by the last update's walk for a pair whose ends are as
  // they were: the same numbers).
  const auto endTermsNow = [&] {
    EndTerms ends;
    // The unoccluded transfer of each pair. Between elements, each receiver point's row is scaled
    // to its exact point-to-element form factor (Lambert's formula): the source's cubature points
    // alone miss the kernel's peak where the elements meet (a wall's corner with the floor), and
    // that lost energy (3.4% of a furnace room at tolerance 1e-2, 0.9% at 1e-3); the cubature then
    // only says how the transfer spreads over the source, for its linear coefficients.
    std::array<std::array<double, 4>, 4>& transfers = ends.transfers;
    // Points under a polygon in face-to-face contact see only it, which the ray caster cannot tell.
    std::array<bool, 4> receiverCovered{}, sourceCovered{};
    if (r.isElement())
      for (int i = 0; i < receiver.count; ++i)
        receiverCovered[i] = (elements_[r.index].coveredPoints >> i) & 1u;
    if (s.isElement())
      for (int j = 0; j < source.count; ++j)
        sourceCovered[j] = (elements_[s.index].coveredPoints >> j) & 1u;
    // The exact point form factors at the receiver's points, lowest and highest (elements only).
    double lowestForm = std::numeric_limits<double>::infinity(), highestForm = 0;
    // The largest transfer a cover took away: a partly covered element whose cubature points all
    // lie under the covering polygon reads zero everywhere, while the rest of it may be in the
    // open.
    double coveredHighest = 0;
    // Between elements, the source's bounds: where a receiver point is far from it (kFarSizes),
    // and whether the ends nearly touch (below).
    Box3 sourceBox;
    Vec3 sourceCentre;
    double sourceFar = 0;
    if (!receiver.isCluster && !source.isCluster) {
      sourceBox = elements_[s.index].shape.bounds();
      sourceCentre = sourceBox.center();
      sourceFar = kFarSizes * sourceBox.diagonalLength();
    }
    for (int i = 0; i < receiver.count; ++i) {
      const Vec3& x = receiver.points[i];
      double cubatureSum = 0;
      for (int j = 0; j < source.count; ++j) {
        const Vec3 d = source.points[j] - x;
        const double r2 = dot(d, d);
        if (!(r2 > 0)) continue;
        const double r1 = std::sqrt(r2);
        const double cx = receiver.isCluster ? kClusterCosine : dot(receiver.normal, d) / r1;
        const double cy = source.isCluster ? kClusterCosine : -dot(source.normal, d) / r1;
        if (cx > 0 && cy > 0) transfers[i][j] = sourceArea * cx * cy / (std::numbers::pi * r2);
        cubatureSum += source.weights[j] * transfers[i][j];
      }
      if (!receiver.isCluster && !source.isCluster) {
        // Far from the source the cubature's sum is the form factor already (the kernel is
        // smooth over it): the exact one only where the point is near.
        const bool far = cubatureSum > 0 && length(x - sourceCentre) > sourceFar;
        const double exact =
            far ? cubatureSum
                : pointToElementFormFactor(x, receiver.normal, elements_[s.index].shape);
        lowestForm = std::min(lowestForm, exact);
        highestForm = std::max(highestForm, exact);
        for (int j = 0; j < source.count; ++j)
          transfers[i][j] = cubatureSum > 0 ? transfers[i][j] * (exact / cubatureSum) : exact;
      } else {
        // A pair's transfer is at most what a source facing the receiver wholly would send (1, in
        // units of the cluster cosines): where the points nearly meet the bare kernel would send
        // more than the source emits.
        const double most =
            (receiver.isCluster ? kClusterCosine : 1) * (source.isCluster ? kClusterCosine : 1);
        for (int j = 0; j < source.count; ++j) transfers[i][j] = std::min(most, transfers[i][j]);
      }
      // An element end's covered points neither receive nor send (a cluster end has none).
      for (int j = 0; j < source.count; ++j)
        if (receiverCovered[i] || sourceCovered[j]) {
          coveredHighest = std::max(coveredHighest, transfers[i][j]);
          transfers[i][j] = 0;
        }
    }
    // Where two elements nearly touch face to face (a sideboard's back 1 cm from the wall), the
    // kernel is a step from nothing to everything across the receiver that all its Gauss points
    // can miss: in the furnace the sideboard's back read 0.08-0.3 where every point sees the wall
    // whole. The exact point form factors a quarter of the way in from the receiver's corners
    // join the spread there.
    if (!receiver.isCluster && !source.isCluster) {
      const GElement &to = elements_[r.index], &from = elements_[s.index];
      const Box3 a = to.shape.bounds(), &b = sourceBox;
      Vec3 gap;
      for (int k = 0; k < 3; ++k)
        gap[k] = std::max({0.0, a.min[k] - b.max[k], b.min[k] - a.max[k]});
      if (length(gap) < kNearShare * std::max(a.diagonalLength(), b.diagonalLength())) {
        const Vec3 centre = to.shape.centroid();
        const auto sampleAt = [&](const Vec3& x) {
          const double form = pointToElementFormFactor(x, to.shape.normal, from.shape);
          lowestForm = std::min(lowestForm, form);
          highestForm = std::max(highestForm, form);
        };
        for (int k = 0; k < to.shape.vertexCount; ++k)
          sampleAt(to.shape.vertices[k] + (centre - to.shape.vertices[k]) * 0.25);
        // And right in front of a source much smaller than the receiver (a sofa's back in front
        // of a wall): the source's centre seen straight across, when that falls on the receiver.
        const Vec3 across = from.shape.centroid() -
                            to.shape.normal * dot(from.shape.centroid() - centre, to.shape.normal);
        if (to.shape.insideness(across) > 0) sampleAt(across);
        ends.nearSpread = highestForm - lowestForm;
        ends.near = true;
      }
    }
    ends.coveredHighest = coveredHighest;
    // A cluster end takes or gives its light along the one direction between the ends' centres
    // (its lobes): the error is what a surface facing the other end could take (the kernel with
    // the cluster's cosine 1, at most the whole source's light) times how far the directions
    // between the points stray from that one (1 − the least cosine).
    if ((receiver.isCluster || source.isCluster) && options_.directionWeight > 0) {
      double leastCosine = 1, facing = 0;
      for (int i = 0; i < receiver.count; ++i)
        for (int j = 0; j < source.count; ++j) {
          const Vec3 d = source.points[j] - receiver.points[i];
          const double r2 = dot(d, d);
          if (!(r2 > 0)) continue;
          const double r1 = std::sqrt(r2);
          leastCosine = std::min(leastCosine, dot(d, direction) / r1);
          const double cx = receiver.isCluster ? 1 : dot(receiver.normal, d) / r1;
          const double cy = source.isCluster ? 1 : -dot(source.normal, d) / r1;
          if (cx > 0 && cy > 0)
            facing += receiver.weights[i] * source.weights[j] *
                      std::min(1.0, sourceArea * cx * cy / (std::numbers::pi * r2));
        }
      ends.wideSpread = options_.directionWeight * (1 - leastCosine) * facing;
    }
    // No point pair faces, yet the ends can exchange light (each has a point in front of the
    // other): the cubature points lie where the other end is behind them, the estimate reads
    // zero with zero spread, and the oracle would never split the pair. In the Cornell box a
    // block's side stands on the floor facing away from its middle: the floor's four cluster
    // points and its Gauss points lay behind the side, and the 21% of the side's light that
    // falls on the floor (an independent ray count) was lost. Such a pair's spread is what a
    // transfer can be where its points do not look: between elements the receiver's exact point
    // form factor at its corners (one lies in front of the source), at a cluster end the cap.
    const bool facesSomewhere =
        std::any_of(transfers.begin(), transfers.end(), [](const std::array<double, 4>& row) {
          return std::any_of(row.begin(), row.end(), [](double t) { return t > 0; });
        });
    if (!facesSomewhere && coveredHighest == 0) {
      if (!receiver.isCluster && !source.isCluster) {
        const ElementShape& to = elements_[r.index].shape;
        for (int k = 0; k < to.vertexCount; ++k)
          ends.blindSpread = std::max(
              ends.blindSpread,
              pointToElementFormFactor(to.vertices[k], to.normal, elements_[s.index].shape));
      } else {
        ends.blindSpread =
            (receiver.isCluster ? kClusterCosine : 1) * (source.isCluster ? kClusterCosine : 1);
      }
    }
    return ends;
  };
  // The candidates' bounds, grown by the ray caster's tolerance (it works in single precision).
  // Past a few candidates a ray costs less than testing its segment against every box (measured
  // on the furnished room, one core: a build 0.73 s with the boxes always tested, 0.46 s past 16).
  const bool testEveryRay = candidates.count > kMostBoxesTested;
  std::vector<Box3> candidateBoxes;
  if (!testEveryRay && mayBeHidden) {
    CHECK(candidates.ids && candidates.ids->size() == candidates.count);
    candidateBoxes.reserve(candidates.count);
    for (PolygonId id : *candidates.ids)
      candidateBoxes.push_back(polygonBounds_[id].expanded(rays_->epsilon()));
  }
  double hiddenTransfer = 0;
  Estimate e;
  e.ends = reuse && reuse->ends ? *reuse->ends : endTermsNow();
  const std::array<std::array<double, 4>, 4>& transfers = e.ends.transfers;
  double lowest = std::numeric_limits<double>::infinity(), highest = 0;
  // With a cluster end, its lobe weights: the point pairs' directions weighed by what they carry.
  std::array<double, 6> lobes{};
  double carried = 0;
  for (int i = 0; i < receiver.count; ++i) {
    const Vec3& x = receiver.points[i];
    for (int j = 0; j < source.count; ++j) {
      const Vec3& y = source.points[j];
      ++counters.pointPairs;
      double transfer = transfers[i][j];
      if (transfer > 0 && mayBeHidden) {
        // A cluster is transparent to its own contents (its lobes already say which way they
        // face): the part of the segment inside a cluster end's box is not tested.
        const Vec3 d = y - x;
        double from = 0, to = 1;
        if (receiver.isCluster) from = receiver.box.segmentInterval(x, y).second;
        if (source.isCluster) to = source.box.segmentInterval(x, y).first;
        if (from < to) {
          const Vec3 a = x + d * from, b = x + d * to;
          const std::uint16_t bit = std::uint16_t(1u << (4 * i + j));
          bool hidden = false;
          const auto missesMoved = [&] {
            return std::none_of(reuse->movedBoxes->begin(), reuse->movedBoxes->end(),
                                [&](const Box3& box) { return box.meetsSegment(a, b); });
          };
          if (reuse && reuse->everyRay == testEveryRay && (reuse->sameCover & bit) &&
              missesMoved()) {
            hidden = (reuse->hiddenPairs & bit) != 0;
            ++counters.reusedRays;
          } else {
            if (testEveryRay) {
              ++counters.visibilityRays;
              hidden = rays_->isOccluded(a, b);
            } else {
              // A few candidates: the segment is tested against those whose boxes it meets (most
              // segments of a link whose shaft holds a polygon pass beside it), each polygon
              // exactly, by the ray caster's rule, without a ray through the whole scene (a
              // ray cost several times a polygon's test: a quarter of a Cornell box solve).
              bool asked = false;
              const SegmentBoxTest segment(a, b);
              for (size_t k = 0; k < candidateBoxes.size() && !hidden; ++k) {
                if (!segment.meets(candidateBoxes[k])) continue;
                asked = true;
                const WorldPolygon& polygon = scene_.polygons[(*candidates.ids)[k]];
                hidden =
                    segmentCrossesPolygon(a, b, polygon.vertices, polygon.plane, rays_->epsilon());
              }
              if (asked) ++counters.visibilityRays;
            }
          }
          if (hidden) {
            e.hiddenPairs |= bit;
            hiddenTransfer += receiver.weights[i] * source.weights[j] * transfer;
            transfer = 0;
          }
        }
      }
      lowest = std::min(lowest, transfer);
      highest = std::max(highest, transfer);
      const double w = receiver.weights[i] * source.weights[j] * transfer;
      if ((receiver.isCluster || source.isCluster) && w > 0) {
        const Vec3 d = normalize(y - x);  // towards the source (w > 0: the points differ)
        for (int k = 0; k < 3; ++k) lobes[2 * k + (d[k] < 0 ? 1 : 0)] += std::abs(d[k]) * w;
        carried += w;
      }
      for (int beta = 0; beta < 3; ++beta)
        for (int alpha = 0; alpha < 3; ++alpha)
          e.k[beta * 3 + alpha] += w * receiver.basis[i][beta] * source.basis[j][alpha];
    }
  }
  e.everyRay = testEveryRay;
  e.meanTransfer = e.k[0];
  e.spread = highest - lowest;
  if (e.ends.near) e.spread = std::max(e.spread, e.ends.nearSpread);
  e.spread = std::max(e.spread, e.ends.blindSpread);
  e.spread = std::max(e.spread, e.ends.wideSpread);
  // Over a partly covered end the transfer runs from nothing (under the cover) to what the
  // covered points would receive in the open: the spread a linear function cannot follow, so that
  // refinement splits along the contact's outline even where no cubature point is in the open.
  e.spread = std::max(e.spread, e.ends.coveredHighest);
  e.hiddenTransfer = hiddenTransfer;
  // A cluster end's coefficient in its own units: per unit of the exitance a source cluster's
  // lobes send (B A, so without its area and cosine), as the flux density arriving at a receiver
  // cluster (its lobes take the cosines of its surfaces).
  const double scale = (s.isCluster() ? 1 / (kClusterCosine * sourceArea) : 1) *
                       (r.isCluster() ? 1 / kClusterCosine : 1);
  for (double& k : e.k) k *= scale;
  if (carried > 0) {
    for (int f = 0; f < 6; ++f) e.lobes[f] = float(lobes[f] / carried);
  } else if (r.isCluster() || s.isCluster()) {
    // Nothing carried: the direction between the centres (the weights carry nothing).
    e.lobes = lobeWeightsOf(direction);
  }
  return e;
}

}  // namespace penumbra
