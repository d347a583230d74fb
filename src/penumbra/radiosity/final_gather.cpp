// Final gather (Smits, Arvo & Greenberg 1994; Lischinski, Tampieri & Greenberg 1993): the leaves'
// irradiance re-gathered at their own points from every active link above them, and the leaves'
// radiosities solved again with it.
//
// Gathering hands a receiver the mean of what its links bring, and push-pull hands that mean on
// to every leaf below: a wall element linked as a whole to the part of another wall 1 cm in front
// of half of it passes half a hemisphere to each of its leaves, where one half sees all of it and
// the other none; a cluster receiver passes the same irradiance to a chair's seat and to the
// underside of that seat. The power oracle lets such a mean stand wherever it carries little
// power (a small receiver, a small cluster), so the leaves' irradiance strays by tens of percent
// where the energy balance is exact.
//
// Here each of a leaf's 16 grandchild cells takes what the sources of the active links above the
// leaf (its element ancestors' links and those of the clusters holding its polygon) send to it.
// Those sources tile the scene as seen from the leaf, so over a cell their visible form factors
// sum to the part of the hemisphere that meets a surface: 1 in a closed scene.
//  - Exact sources: element sources wholly visible from the leaf (no polygon meets their shaft),
//    and lamps (emitting more than RadiosityOptions::exactGatherContrast x the mean radiosity),
//    whose shadows rays would leave noisy. Their form factor is the cell's mean where the source
//    is near (the links' adaptive quadrature), the centre's value elsewhere, a partly hidden
//    lamp's scaled by its exact visible fraction at the centre (the source minus the central
//    projections of the polygons in the shaft, as the exact reference clips a light); they send
//    the source's radiosity.
//  - Ray sources: partly hidden element sources and the root elements of cluster sources.
//    Cosine-distributed rays from points of the cell take the radiosity of the cell of the leaf
//    they meet, its own direct and indirect light (0 on a back face: polygons emit and reflect
//    from their front only), so a source's part hidden from the cell, often the part in shadow,
//    is not sent at the visible part's visibility, nor with the light of its shadowed cells. Rays
//    meeting an exact source are already counted; the others share what the exact ones leave of
//    the hemisphere, 1 − Σ exact (a ratio estimator, Hammersley & Handscomb 1964 §5.5): the sum
//    over the cell is then 1 in a closed scene whatever the rays' noise, and the noise stays in
//    how the remainder is split.
//  - A cell covered by a polygon in contact (a box's bottom on the floor) sees only that polygon,
//    and a leaf partly covered sends the room the radiosity of its exposed cells.
// The leaves' and their cells' radiosities are then solved again by Jacobi iteration over these
// transfers, starting from the hierarchical solution: the answer shown (mesh, probes) and its
// energy balance are those of this final solution. The hierarchical solution
// (NodeRadiometry::irradianceDirect / Indirect) is what refinement follows; it is kept for
// comparison.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <tuple>
#include <vector>

#include "penumbra/base/parallel_for.h"
#include "penumbra/base/split_mix.h"
#include "penumbra/geometry/cosine_direction.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/spatial/ray_caster.h"

namespace penumbra {

struct RadiositySolver::GatherEntry {
  int element = 0;
  // A ray's entry: the cell of the leaf it met (grandchildContaining), whose own radiosity it
  // takes (cellReflected_); -1: the element's mean (exact sources, and the rays' fallback).
  std::int8_t cell = -1;
  std::int8_t at = -1;  // the receiving leaf's cell that gathered it
  double weight = 0;
};

// What a leaf gathers at its exposed points and at its points covered by a polygon in contact.
struct RadiositySolver::LeafGather {
  std::vector<GatherEntry> exposed;  // transfers from sources, per exposed point
  std::vector<GatherEntry> covered;  // the covering leaves, per covered point
  int coveredPoints = 0;
  // Counted per leaf (leaves are gathered in parallel), summed into the statistics after.
  long long rays = 0, misses = 0, clippedPoints = 0;
  // With RadiosityOptions::exactDirect: the direct irradiance, the mean of that function over the
  // exposed points (nothing when it answered nothing at one of them).
  std::optional<Rgb> exactDirect;
  // Each cell's direct irradiance (the exact function at its point, or what its entries bring
  // from emission), and which cells are covered by a polygon in contact.
  std::array<Rgb, 16> cellDirect{};
  std::uint16_t coveredCells = 0;
  // Gathers at a point (gatheredIndirect) with an exact direct part: rays that meet a leaf
  // closer than its size are kept apart, where they met it (continued there: reflectedAlong).
  bool keepNearHits = false;
  // Cast rounds of rays until a quarter of a round's count met something that sends light (not
  // only something): a point outside the Cornell box's opening, among black walls, sees the lit
  // inside through a sliver of its hemisphere, and with one round its 1,024 rays met it some 50
  // times (errors of ±25%). Off for the cells of a leaf that reflects nothing: nothing it sends
  // depends on them.
  bool untilLight = false;
  struct NearHit {
    int leaf = 0;
    Vec3 point;
    PolygonId polygon = 0;
    double weight = 0;
  };
  std::vector<NearHit> near;
};

// The leaf's 16 grandchild centres, nudged by a ten-thousandth of the leaf along two
// incommensurate directions: subdivision puts centres on round coordinates, where modelled
// features often lie (a door's edge on a sideboard), and a centre on the edge of a polygon in
// contact is neither covered nor free.
std::array<Vec3, 16> RadiositySolver::gatherPoints(const Element& leaf) {
  const Vec3 nudge = (leaf.vertices[1] - leaf.vertices[0]) * 1.2345e-4 +
                     (leaf.vertices[leaf.vertexCount - 1] - leaf.vertices[0]) * 0.9876e-4;
  std::array<Vec3, 16> points = leaf.grandchildCentres();
  for (Vec3& x : points) x += nudge;
  return points;
}

int RadiositySolver::leafAt(PolygonId polygon, const Vec3& y) const {
  int best = -1;
  double inside = -std::numeric_limits<double>::infinity();
  for (int root : polygonRoots_[polygon])
    if (const double d = elements_[root].insideness(y); d > inside) best = root, inside = d;
  while (best >= 0 && !elements_[best].isLeaf())
    best = elements_[best].firstChild + elements_[best].childContaining(y);
  return best;
}

int RadiositySolver::coveringLeaf(PolygonId polygon, const Vec3& x) const {
  for (PolygonId partner : contacts_[polygon])
    // Only a polygon in contact face to face is what the point sees; one lying on it facing the
    // same way (coveringPolygons) hides the point from everything.
    if (dot(scene_.polygons[partner].plane.normal, scene_.polygons[polygon].plane.normal) < 0)
      for (int root : polygonRoots_[partner])
        if (elements_[root].insideness(x) > 0) return leafAt(partner, x);
  return -1;
}

void RadiositySolver::indexGatherSources() {
  GatherIndex& g = gatherIndex_;
  g.elementLinks.assign(elements_.size(), {});
  g.clusterLinks.assign(clusters_.size(), {});
  for (size_t i = 0; i < links_.size(); ++i)
    if (links_[i].active)
      (links_[i].receiver.isCluster() ? g.clusterLinks : g.elementLinks)[links_[i].receiver.index]
          .push_back(int(i));
  g.parentCluster.assign(clusters_.size(), -1);
  g.rootCluster.assign(elements_.size(), -1);
  for (size_t c = 0; c < clusters_.size(); ++c)
    for (NodeRef child : clusters_[c].children)
      (child.isCluster() ? g.parentCluster : g.rootCluster)[child.index] = int(c);
  // Sources emitting more than exactGatherContrast x the mean radiosity of the scene's surfaces
  // (the lamps) are gathered exactly even where partly hidden. Emission, not radiosity: a
  // reflector's radiosity varies over it with its shadows, and gathered at its mean radiosity a
  // partly hidden one would send its hidden, often shadowed, part's light at the visible part's
  // visibility.
  double areaSum = 0, radiositySum = 0;
  for (const Element& e : elements_)
    if (e.isLeaf()) {
      areaSum += e.area;
      radiositySum += e.area * e.radiometry.maxRadiosity;
    }
  g.brightRadiosity = options_.exactGatherContrast * radiositySum / areaSum;
}

// The active links above the leaf. Gathered exactly: element sources wholly visible from the
// leaf (no polygon meets their shaft) and bright ones (the lamps), whose shadows rays would leave
// noisy. The others, and the root elements of cluster sources, by rays: they send the radiosity
// of the leaf each ray meets, so a source's part hidden from the leaf, often the part in shadow
// (the floor under a crate, a wall behind a sofa), is not sent at the mean radiosity of the
// whole source.
RadiositySolver::LeafSources RadiositySolver::leafSources(int id) const {
  const GatherIndex& g = gatherIndex_;
  const Element& leaf = elements_[id];
  LeafSources sources;
  const auto collect = [&](const std::vector<int>& links) {
    for (int index : links) {
      const NodeRef s = links_[index].source;
      if (s.isCluster()) {
        for (int i = clusters_[s.index].elementBegin; i < clusters_[s.index].elementEnd; ++i)
          sources.rayElements.push_back(rootOrder_[i]);
        continue;
      }
      std::vector<PolygonId> hiding = shaftOccluders(leaf, elements_[s.index]);
      if (!hiding.empty() && !(radiometry(s).emission.maxComponent() > g.brightRadiosity)) {
        sources.rayElements.push_back(s.index);
        continue;
      }
      sources.exactLinks.push_back(index);
      sources.occluders.push_back(std::move(hiding));
      sources.exactSources.push_back(s.index);
    }
  };
  int root = id;
  for (int e = id; e >= 0; e = elements_[e].parent) {
    collect(g.elementLinks[e]);
    root = e;
  }
  for (int c = g.rootCluster[root]; c >= 0; c = g.parentCluster[c]) collect(g.clusterLinks[c]);
  std::sort(sources.exactSources.begin(), sources.exactSources.end());
  return sources;
}

void RadiositySolver::finalGather() {
  indexGatherSources();
  std::vector<LeafGather> gathered(elements_.size());
  // The exact direct irradiance at the leaves' exposed points, on this thread: the function may
  // not be thread-safe (the discontinuity mesh's exact arrangements cache lazily).
  if (options_.exactDirect)
    for (size_t id = 0; id < elements_.size(); ++id) {
      const Element& leaf = elements_[id];
      if (!leaf.isLeaf()) continue;
      Rgb sum;
      int count = 0;
      bool answered = true;
      const std::array<Vec3, 16> points = gatherPoints(leaf);
      for (int k = 0; k < 16; ++k) {
        if (isCovered(leaf.polygon, points[k])) continue;
        const std::optional<Rgb> e = options_.exactDirect(points[k], leaf.normal, leaf.polygon);
        answered = e.has_value();
        if (!answered) break;
        gathered[id].cellDirect[k] = *e;
        sum += *e;
        ++count;
      }
      if (answered && count > 0) gathered[id].exactDirect = sum / double(count);
    }
  // Each leaf reads the hierarchy and writes only its own LeafGather, with a random stream of its
  // own: the result is the same for any number of threads.
  parallelFor((long long)elements_.size(), options_.threads, [&](long long id) {
    if (!elements_[id].isLeaf()) return;
    const Element& leaf = elements_[id];
    const LeafSources sources = leafSources(int(id));
    const std::vector<int>& exactLinks = sources.exactLinks;
    const std::vector<int>& rayElements = sources.rayElements;
    const std::vector<int>& exactSources = sources.exactSources;
    const std::vector<std::vector<PolygonId>>& occluders = sources.occluders;
    const std::vector<PolygonId>& partners = contacts_[leaf.polygon];

    SplitMix rng(options_.seed * 0x9e3779b97f4a7c15ull + id);
    LeafGather& leafGather = gathered[id];
    leafGather.untilLight = leaf.reflectance.maxComponent() > 0;
    std::vector<GatherEntry>& entries = leafGather.exposed;
    // Each of the leaf's 16 grandchild cells gathers the mean over the cell of what arrives, so
    // that the receivers integrate what a source sends as the links' quadrature does: the point
    // form factor to a source sharing an edge with the receiver (a wall's elements seen from
    // the floor along it) peaks at that edge, between the cells' centres. The cell's (nudged)
    // centre says whether the cell is covered by a polygon in contact (gatherPoints).
    const std::array<Vec3, 16> points = gatherPoints(leaf);
    const std::array<std::array<Vec3, 4>, 16> cells = leaf.grandchildCells();
    const double cellSize = std::sqrt(leaf.area / 16);
    for (int k = 0; k < 16; ++k) {
      const Vec3& x = points[k];
      if (isCovered(leaf.polygon, x)) {
        // x sees only the polygon covering it.
        ++leafGather.coveredPoints;
        leafGather.coveredCells |= std::uint16_t(1u << k);
        if (const int h = coveringLeaf(leaf.polygon, x); h >= 0)
          leafGather.covered.push_back({.element = h, .weight = 1});
        continue;
      }
      const size_t cellBegin = entries.size();
      double exactSum = 0;
      for (size_t j = 0; j < exactLinks.size(); ++j) {
        const Link& link = links_[exactLinks[j]];
        const Element& source = elements_[link.source.index];
        // A polygon in contact lies in x's plane: it sends x nothing unless it covers x (above).
        if (std::find(partners.begin(), partners.end(), source.polygon) != partners.end()) continue;
        const double f = unoccludedPointTransfer(link, x, leaf.normal, false);
        // The cell's mean where the source is near (within four cells); the centre's value
        // elsewhere, where the point form factor varies little over the cell.
        const bool near = distance(x, source.bounds()) < 4 * cellSize;
        const double mean = near ? cellFormFactor(cells[k], leaf, source) : f;
        if (!(mean > 0)) continue;
        // Visibility at the centre, applied to the cell's mean.
        const double visible =
            f > 0 ? mean *
                        visibleTransfer(x, leaf.normal, leaf.polygon, source, occluders[j], f,
                                        leafGather.clippedPoints) /
                        f
                  : (occluders[j].empty() ? mean : 0.0);
        if (visible > 0) entries.push_back({.element = link.source.index, .weight = visible});
        exactSum += visible;
      }
      const double remainder = 1 - exactSum;
      if (!rayElements.empty() && remainder > 0)
        splitRemainder(leaf, cells[k], x, remainder, rayElements, exactSources,
                       options_.finalGatherRays, rng, leafGather);
      Rgb direct;
      for (size_t i = cellBegin; i < entries.size(); ++i) {
        entries[i].at = std::int8_t(k);
        direct += elements_[entries[i].element].radiometry.emission * entries[i].weight;
      }
      if (!leafGather.exactDirect) leafGather.cellDirect[size_t(k)] = direct;
    }
    // One entry per receiving cell and source (element, or cell of a leaf), weights per point of
    // its kind (their sum over a leaf's list is the mean over those points).
    const auto merge = [](std::vector<GatherEntry>& list, int points) {
      const auto key = [](const GatherEntry& g) { return std::tuple(g.at, g.element, g.cell); };
      std::sort(list.begin(), list.end(),
                [&](const GatherEntry& a, const GatherEntry& b) { return key(a) < key(b); });
      size_t merged = 0;
      for (size_t i = 0; i < list.size(); ++i) {
        if (merged > 0 && key(list[merged - 1]) == key(list[i]))
          list[merged - 1].weight += list[i].weight;
        else
          list[merged++] = list[i];
      }
      list.resize(merged);
      for (GatherEntry& g : list) g.weight /= std::max(points, 1);
    };
    merge(leafGather.exposed, 16 - leafGather.coveredPoints);
    merge(leafGather.covered, leafGather.coveredPoints);
  });
  for (const LeafGather& g : gathered) {
    stats_.finalGatherRays += g.rays;
    stats_.finalGatherMisses += g.misses;
    stats_.exactVisibilityPoints += g.clippedPoints;
  }
  solveLeaves(gathered);
}

// What the exact sources leave of x's hemisphere, `remainder`, split by cosine-distributed rays
// among what they meet outside those sources: the leaf met (its radiosity), or nothing (a back
// face, or no surface). Rays are cast in rounds (at most kRounds) until a quarter of a round's
// count has met something outside the exact sources (something that sends light, with
// LeafGather::untilLight); where none does (the remainder is a sliver of the
// hemisphere) or the remainder is below kNoRays of it, it goes to the ray sources' root
// elements in proportion to their unoccluded form factors from x.
void RadiositySolver::splitRemainder(const Element& leaf, const std::array<Vec3, 4>& cell,
                                     const Vec3& x, double remainder,
                                     const std::vector<int>& rayElements,
                                     const std::vector<int>& exactSources, int rayCount,
                                     SplitMix& rng, LeafGather& gather) const {
  std::vector<GatherEntry>& entries = gather.exposed;
  constexpr double kNoRays = 1e-4;
  constexpr int kRounds = 8;
  constexpr double kSeam = 10;
  const int rays = std::max(0, rayCount);
  // What each ray met: a leaf and its cell, or nothing (leaf -1).
  std::vector<std::pair<int, int>> met;
  const size_t nearBefore = gather.near.size();
  if (rays > 0 && remainder > kNoRays) {
    // side² strata, the rays beyond them unstratified: strata left empty would leave a range
    // of directions out of every point's estimate (32 rays in 6 x 6 strata skewed every
    // point's rays away from a sixth of the azimuths, and the Cornell box's left wall was
    // seen 1.09 of its area, its right wall 0.94).
    const int side = std::max(1, int(std::sqrt(double(rays))));
    Element cellElement;
    cellElement.vertices = cell;
    cellElement.vertexCount = leaf.vertexCount;
    const std::vector<PolygonId>& partners = contacts_[leaf.polygon];
    const auto isExact = [&](int h) {
      for (int e = h; e >= 0; e = elements_[e].parent)
        if (std::binary_search(exactSources.begin(), exactSources.end(), e)) return true;
      return false;
    };
    // Rays that met something, and those of them that met something sending light.
    int lit = 0;
    const auto enough = [&] { return 4 * (gather.untilLight ? lit : int(met.size())) >= rays; };
    for (int round = 0; round < kRounds && !enough(); ++round)
      for (int r = 0; r < rays; ++r) {
        // Stratified on the unit disc, lifted to the hemisphere.
        const bool stratified = r < side * side;
        const double a = stratified ? (r % side + rng.uniform()) / side : rng.uniform();
        const double turn = stratified ? (r / side + rng.uniform()) / side : rng.uniform();
        const Vec3 d = cosineDirection(leaf.normal, a, turn);
        ++gather.rays;
        // From a point uniform in the cell (the cell's mean, as the exact sources give it); one
        // covered by a polygon in contact sees nothing else and says nothing here. (Drawn v
        // first, then u, in sequence: function arguments are not.)
        const double v = rng.uniform(), u = rng.uniform();
        const Vec3 origin = cellElement.samplePoint(u, v);
        if (!partners.empty() && isCovered(leaf.polygon, origin)) continue;
        // Polygons within the caster's epsilon of the origin are not met: a duplicate of the leaf's
        // own polygon (a double-modelled face) would be met at t = 0, from behind. Of a two-sided
        // card, the side facing the ray is met.
        const auto hit = firstSurfaceSeen(*rays_, scene_, origin, d, rays_->epsilon(),
                                          std::numeric_limits<double>::infinity(), leaf.polygon);
        if (!hit) {
          ++gather.misses;
          met.push_back({-1, 0});
          continue;
        }
        const bool front = dot(scene_.polygons[hit->polygon].plane.normal, d) < 0;
        // A back face met through a surface the ray left within the caster's epsilon of its
        // origin (an origin a hair beside a book standing on a shelf: the ray passes the
        // book's near side, closer than epsilon, and meets its far side from inside) or met
        // right away (an origin at a door's edge) is a seam the ray slipped into, not a view of
        // the back of something: such rays say nothing.
        if (!front) {
          if (hit->t < kSeam * rays_->epsilon()) continue;
          const auto first = rays_->intersect(origin, d, 0, rays_->epsilon(), leaf.polygon);
          if (first) continue;
        }
        if (!front) {
          ++gather.misses;
          met.push_back({-1, 0});
          continue;
        }
        // The front of an exact source is already counted; its back is not (it sends nothing,
        // and is part of the remainder like any back face: the ceiling right above a lamp hung
        // 1 mm below it sees almost nothing but the lamp's back, and skipping those rays gave
        // the few that escape sideways the whole remainder, +54% indirect light there).
        const int h = leafAt(hit->polygon, hit->point);
        if (h >= 0 && isExact(h)) continue;
        // A ray met near counts here like the others, and sends through gather.near.
        const bool near = gather.keepNearHits && h >= 0 && isNearHit(h, hit->t);
        if (near) gather.near.push_back({h, hit->point, hit->polygon, 0});
        if (h >= 0 && (elements_[h].reflectance.maxComponent() > 0 ||
                       elements_[h].radiometry.emission.maxComponent() > 0))
          ++lit;
        met.push_back(near || h < 0 ? std::pair{-1, 0}
                                    : std::pair{h, elements_[h].grandchildContaining(hit->point)});
      }
  }
  if (!met.empty()) {
    const double weight = remainder / double(met.size());
    for (const auto& [h, cell] : met)
      if (h >= 0) entries.push_back({.element = h, .cell = std::int8_t(cell), .weight = weight});
    for (size_t k = nearBefore; k < gather.near.size(); ++k) gather.near[k].weight = weight;
    return;
  }
  std::vector<double> formFactors(rayElements.size());
  double total = 0;
  for (size_t k = 0; k < rayElements.size(); ++k)
    total += formFactors[k] = pointFormFactor(x, leaf.normal, elements_[rayElements[k]]);
  if (!(total > 0)) return;
  for (size_t k = 0; k < rayElements.size(); ++k)
    if (formFactors[k] > 0)
      entries.push_back({.element = rayElements[k], .weight = remainder * formFactors[k] / total});
}

// Jacobi iteration over the leaves' point transfers, from the hierarchical solution. A leaf
// partly covered by a polygon in contact (the floor's leaves along a crate's foot) has two
// radiosities: over its exposed points, which is what every other surface sees of it, and over
// its covered points, which only the covering polygon sees. Sending the leaf's mean to the room
// would send the dark covered part's light from the exposed part. So: E_exposed = Σ exposed weight
// x B_exposed(element), E_covered = Σ covered weight x B_covered(leaf), each B = M + ρ E of its
// kind, the leaf's E the mean over its 16 points; inner elements' B_exposed (what exact sources
// send) the area mean of their leaves' (children are stored after their parents, so one backward
// sweep pulls them up).
void RadiositySolver::solveLeaves(const std::vector<LeafGather>& gathered) {
  const size_t count = elements_.size();
  std::vector<Rgb> exposedReflected(count), coveredReflected(count), cellReflected(count * 16);
  for (size_t id = 0; id < count; ++id) {
    exposedReflected[id] = coveredReflected[id] = elements_[id].radiometry.reflected;
    std::fill_n(cellReflected.begin() + std::ptrdiff_t(id * 16), 16, exposedReflected[id]);
  }
  const auto sum = [&](const std::vector<GatherEntry>& list, const auto& value) {
    Rgb total;
    for (const GatherEntry& g : list) total += value(g) * g.weight;
    return total;
  };
  const auto emission = [&](const GatherEntry& g) {
    return elements_[g.element].radiometry.emission;
  };
  std::vector<Rgb> exposedDirect(count), coveredDirect(count);
  for (size_t id = 0; id < count; ++id)
    if (elements_[id].isLeaf()) {
      const LeafGather& g = gathered[id];
      exposedDirect[id] = g.exactDirect ? *g.exactDirect : sum(g.exposed, emission);
      coveredDirect[id] = sum(gathered[id].covered, emission);
    }
  std::vector<Rgb> exposedIndirect(count), coveredIndirect(count), cellIndirect(count * 16);
  double scale = 1e-300;
  for (int iteration = 0; iteration < options_.maxIterations; ++iteration) {
    for (size_t id = 0; id < count; ++id)
      if (elements_[id].isLeaf()) {
        // Each exposed cell's own indirect irradiance, and their mean.
        std::array<Rgb, 16> cells{};
        for (const GatherEntry& g : gathered[id].exposed)
          cells[size_t(g.at)] +=
              (g.cell >= 0 ? cellReflected[size_t(g.element) * 16 + size_t(g.cell)]
                           : exposedReflected[size_t(g.element)]) *
              g.weight;
        Rgb mean;
        for (int k = 0; k < 16; ++k) {
          mean += cells[size_t(k)];
          cellIndirect[id * 16 + size_t(k)] =
              cells[size_t(k)] * double(16 - gathered[id].coveredPoints);
        }
        exposedIndirect[id] = mean;
        coveredIndirect[id] = sum(gathered[id].covered, [&](const GatherEntry& g) {
          return coveredReflected[size_t(g.element)];
        });
      }
    double largestChange = 0;
    for (size_t id = 0; id < count; ++id) {
      Element& e = elements_[id];
      if (!e.isLeaf()) continue;
      NodeRadiometry& m = e.radiometry;
      const double covered = gathered[id].coveredPoints / 16.0;
      m.finalDirect = exposedDirect[id] * (1 - covered) + coveredDirect[id] * covered;
      m.finalIndirect = exposedIndirect[id] * (1 - covered) + coveredIndirect[id] * covered;
      const Rgb exposed = e.reflectance * (exposedDirect[id] + exposedIndirect[id]);
      const Rgb hidden = e.reflectance * (coveredDirect[id] + coveredIndirect[id]);
      const Rgb b = m.emission + e.reflectance * (m.finalDirect + m.finalIndirect);
      const Rgb change = b - m.radiosity;
      largestChange =
          std::max({largestChange, std::abs(change.r), std::abs(change.g), std::abs(change.b)});
      scale = std::max(scale, b.maxComponent());
      m.radiosity = b;
      m.reflected = b - m.emission;
      // A kind with no points takes the other's (a leaf wholly covered is seen by no one else).
      exposedReflected[id] = covered < 1 ? exposed : hidden;
      coveredReflected[id] = covered > 0 ? hidden : exposed;
      // What a ray meeting one of the leaf's cells takes (cellReflected_).
      const LeafGather& g = gathered[id];
      for (size_t k = 0; k < 16; ++k)
        cellReflected[id * 16 + k] =
            (g.coveredCells >> k & 1)
                ? hidden
                : e.reflectance * (g.cellDirect[k] + cellIndirect[id * 16 + k]);
    }
    for (size_t i = count; i-- > 0;) {
      Element& e = elements_[i];
      if (e.isLeaf()) continue;
      Rgb radiosity, reflected, exposed;
      for (int k = 0; k < 4; ++k) {
        const int child = e.firstChild + k;
        const double area = elements_[child].area;
        radiosity += elements_[child].radiometry.radiosity * area;
        reflected += elements_[child].radiometry.reflected * area;
        exposed += exposedReflected[child] * area;
      }
      e.radiometry.radiosity = radiosity / e.area;
      e.radiometry.reflected = reflected / e.area;
      exposedReflected[i] = exposed / e.area;
    }
    stats_.finalIterations = iteration + 1;
    if (largestChange / scale < options_.convergence) break;
  }
  exposedReflected_ = std::move(exposedReflected);
  coveredReflected_ = std::move(coveredReflected);
  cellReflected_ = std::move(cellReflected);
}

// A wholly visible source closer to the point than its own size (the wall 1.5 cm beside a point
// of the ceiling fills half its hemisphere) moved from the exact sources to the rays: the strip of
// it next to the point, which sends the point most, is darker than the cells it lies in (the
// corner hides the room from it), and a ray that meets a leaf that close takes what the point it
// met reflects (reflectedAlong). Gathered by its form factor with its leaves' means, such
// points of the furnished room's ceiling read 4-7% too much, and a point of the Cornell box's
// back wall 1.4 mm below its ceiling 24% (bench/radiosity_error_curve --combined --worst).
RadiositySolver::LeafSources RadiositySolver::nearSourcesByRays(const Vec3& point,
                                                                LeafSources sources) const {
  LeafSources kept;
  kept.rayElements = std::move(sources.rayElements);
  for (size_t j = 0; j < sources.exactLinks.size(); ++j) {
    const int source = links_[sources.exactLinks[j]].source.index;
    const Box3 bounds = elements_[source].bounds();
    if (sources.occluders[j].empty() && distance(point, bounds) < bounds.diagonalLength()) {
      kept.rayElements.push_back(source);
      continue;
    }
    kept.exactLinks.push_back(sources.exactLinks[j]);
    kept.occluders.push_back(std::move(sources.occluders[j]));
    kept.exactSources.push_back(source);
  }
  std::sort(kept.exactSources.begin(), kept.exactSources.end());
  return kept;
}

// The final gather at one point instead of a leaf's 16 cells, for the reflected light only (what
// the leaves send beyond their emission): the same sources, each exact one's point form factor
// and exact visibility at the point, the rest by rays from the point.
std::optional<Rgb> RadiositySolver::gatheredIndirect(const Vec3& point, const Vec3& normal,
                                                     int rays, std::uint64_t seed) const {
  if (exposedReflected_.empty()) return std::nullopt;
  const std::optional<int> found = leafContaining(point, normal);
  if (!found) return std::nullopt;
  const int id = *found;
  const Element& leaf = elements_[id];
  if (isCovered(leaf.polygon, point)) {
    // The point sees only the polygon covering it, where that polygon is covered too.
    const int h = coveringLeaf(leaf.polygon, point);
    return h >= 0 ? coveredReflected_[h] : Rgb{};
  }
  const LeafSources sources = nearSourcesByRays(point, leafSources(id));
  const std::vector<PolygonId>& partners = contacts_[leaf.polygon];
  LeafGather gather;
  double exactSum = 0;
  for (size_t j = 0; j < sources.exactLinks.size(); ++j) {
    const Link& link = links_[sources.exactLinks[j]];
    const Element& source = elements_[link.source.index];
    if (std::find(partners.begin(), partners.end(), source.polygon) != partners.end()) continue;
    const double f = unoccludedPointTransfer(link, point, leaf.normal, false);
    if (!(f > 0)) continue;
    const double visible = visibleTransfer(point, leaf.normal, leaf.polygon, source,
                                           sources.occluders[j], f, gather.clippedPoints);
    if (visible > 0) gather.exposed.push_back({.element = link.source.index, .weight = visible});
    exactSum += visible;
  }
  const double remainder = 1 - exactSum;
  Rgb indirect;
  if (!sources.rayElements.empty() && remainder > 0) {
    // Rays from the point itself: a "cell" that is the point.
    const std::array<Vec3, 4> cell{point, point, point, point};
    SplitMix rng(seed);
    gather.keepNearHits = static_cast<bool>(options_.exactDirect);
    gather.untilLight = true;
    splitRemainder(leaf, cell, point, remainder, sources.rayElements, sources.exactSources, rays,
                   rng, gather);
    for (const LeafGather::NearHit& near : gather.near)
      indirect += reflectedAlong(near.leaf, near.point, near.polygon, rng, 0) * near.weight;
  }
  for (const GatherEntry& e : gather.exposed) indirect += reflectedAt(e.element, e.cell) * e.weight;
  return indirect;
}

Rgb RadiositySolver::reflectedAt(int element, int cell) const {
  return cell >= 0 ? cellReflected_[size_t(element) * 16 + size_t(cell)]
                   : exposedReflected_[size_t(element)];
}

bool RadiositySolver::isNearHit(int leaf, double distance) const {
  return distance < elements_[size_t(leaf)].bounds().diagonalLength();
}

// The light a point met closer than its leaf's size reflects: a leaf's radiosity is its mean,
// gathered over all of it, and in a gap narrower than an element (a crate 5 mm from a wall) most
// of the leaf lies outside the gap in the light, so its mean is not what the point reflects.
// There: its reflectance times the exact direct irradiance at the point and the light one
// cosine-distributed ray from it brings (what that ray meets reflects, continued alike where
// met near again, a leaf's mean where met far), a path continued until it leaves the gap.
Rgb RadiositySolver::reflectedAlong(int leaf, const Vec3& point, PolygonId polygon, SplitMix& rng,
                                    int depth) const {
  // Past this many bounces in a row the leaf's mean stands for the rest (a path in a 5 mm gap
  // between walls 0.7 bright keeps 0.7^16 = 0.3% of its weight by then).
  constexpr int kMostBounces = 16;
  const Element& e = elements_[size_t(leaf)];
  const Vec3& normal = scene_.polygons[polygon].plane.normal;
  const std::optional<Rgb> direct =
      depth < kMostBounces ? options_.exactDirect(point, normal, polygon) : std::nullopt;
  // (Drawn in sequence whatever the branch: the numbers each path uses do not depend on it.)
  const double a = rng.uniform(), turn = rng.uniform();
  if (!direct) return exposedReflected_[size_t(leaf)];
  const Vec3 d = cosineDirection(normal, a, turn);
  Rgb indirect;
  const auto hit = firstSurfaceSeen(*rays_, scene_, point, d, rays_->epsilon(),
                                    std::numeric_limits<double>::infinity(), polygon);
  // A back face (a seam the ray slipped into, or the inside of something) sends nothing.
  if (hit && dot(scene_.polygons[hit->polygon].plane.normal, d) < 0) {
    const int h = leafAt(hit->polygon, hit->point);
    if (h >= 0)
      indirect = isNearHit(h, hit->t)
                     ? reflectedAlong(h, hit->point, hit->polygon, rng, depth + 1)
                     : reflectedAt(h, elements_[size_t(h)].grandchildContaining(hit->point));
  }
  return e.reflectance * (*direct + indirect);
}

}  // namespace penumbra
