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
// Here every leaf takes, at its 16 grandchild centres x, what the sources of the active links
// above it (its element ancestors' links and those of the clusters holding its polygon) send to
// x. Those sources tile the scene as seen from the leaf, so at x their visible form factors sum
// to the part of x's hemisphere that meets a surface: 1 in a closed scene.
//  - An element source: its exact visible form factor from x (the source minus the central
//    projections of the polygons meeting the shaft between the leaf and the source, as the exact
//    reference clips a light), times the source's radiosity.
//  - The sources that are clusters: cosine-distributed rays from x, each taking the radiosity of
//    the leaf it meets (0 on a back face: polygons emit and reflect from their front only). Rays
//    that meet an element source of the first kind are already counted exactly; the others share
//    what the exact ones leave of the hemisphere, 1 − Σ exact (a ratio estimator, Hammersley &
//    Handscomb 1964 §5.5): the sum at x is then 1 in a closed scene whatever the rays' noise, and
//    the noise stays in how the remainder is split among the clusters' surfaces.
//  - A point covered by a polygon in contact (a box's bottom on the floor) sees only that polygon.
// The leaves' radiosities are then solved again by Jacobi iteration over these point transfers
// (B_leaf = M + ρ E_leaf, inner elements' B the area mean of their leaves), starting from the
// hierarchical solution: the answer shown (mesh, probes) and its energy balance are those of this
// final solution. The hierarchical solution (NodeRadiometry::irradianceDirect / Indirect) is
// what refinement was driven by; it is kept for comparison.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "penumbra/base/split_mix.h"
#include "penumbra/radiosity/radiosity_solver.h"
#include "penumbra/spatial/ray_caster.h"

namespace penumbra {

struct RadiositySolver::GatherEntry {
  int element = 0;
  double weight = 0;
};

int RadiositySolver::leafAt(PolygonId polygon, const Vec3& y) const {
  int best = -1;
  double inside = -std::numeric_limits<double>::infinity();
  for (int root : polygonRoots_[polygon])
    if (const double d = elements_[root].insideness(y); d > inside) best = root, inside = d;
  while (best >= 0 && !elements_[best].isLeaf()) {
    const int first = elements_[best].firstChild;
    best = first;
    inside = elements_[first].insideness(y);
    for (int k = 1; k < 4; ++k)
      if (const double d = elements_[first + k].insideness(y); d > inside)
        best = first + k, inside = d;
  }
  return best;
}

int RadiositySolver::coveringLeaf(PolygonId polygon, const Vec3& x) const {
  for (PolygonId partner : contacts_[polygon])
    for (int root : polygonRoots_[partner])
      if (elements_[root].insideness(x) > 0) return leafAt(partner, x);
  return -1;
}

void RadiositySolver::finalGather() {
  std::vector<std::vector<int>> elementLinks(elements_.size()), clusterLinks(clusters_.size());
  for (size_t i = 0; i < links_.size(); ++i)
    if (links_[i].active)
      (links_[i].receiver.isCluster() ? clusterLinks : elementLinks)[links_[i].receiver.index]
          .push_back(int(i));
  std::vector<int> parentCluster(clusters_.size(), -1), rootCluster(elements_.size(), -1);
  for (size_t c = 0; c < clusters_.size(); ++c)
    for (NodeRef child : clusters_[c].children)
      (child.isCluster() ? parentCluster : rootCluster)[child.index] = int(c);

  // Sources brighter than exactGatherContrast x the mean radiosity of the scene's surfaces are
  // gathered exactly even where partly hidden.
  double areaSum = 0, radiositySum = 0;
  for (const Element& e : elements_)
    if (e.isLeaf()) {
      areaSum += e.area;
      radiositySum += e.area * e.radiometry.maxRadiosity;
    }
  const double brightRadiosity = options_.exactGatherContrast * radiositySum / areaSum;
  // exactFor[e] == leaf: element e is the source of a link above that leaf gathered exactly.
  std::vector<int> exactFor(elements_.size(), -1);
  std::vector<std::vector<GatherEntry>> gathered(elements_.size());
  for (size_t id = 0; id < elements_.size(); ++id) {
    if (!elements_[id].isLeaf()) continue;
    const Element& leaf = elements_[id];
    // The active links above the leaf. Gathered exactly: element sources wholly visible from the
    // leaf (no polygon meets their shaft) and bright ones (the lamps), whose shadows rays would
    // leave noisy. The others, and the root elements of cluster sources, by rays: they send the
    // radiosity of the leaf each ray meets, so a source's part hidden from the leaf, often the
    // part in shadow (the floor under a crate, a wall behind a sofa), is not sent at the mean
    // radiosity of the whole source.
    std::vector<int> exactLinks, rayElements;
    std::vector<std::vector<PolygonId>> occluders;
    const auto collect = [&](const std::vector<int>& links) {
      for (int index : links) {
        const NodeRef s = links_[index].source;
        if (s.isCluster()) {
          for (int i = clusters_[s.index].elementBegin; i < clusters_[s.index].elementEnd; ++i)
            rayElements.push_back(rootOrder_[i]);
          continue;
        }
        std::vector<PolygonId> hiding = shaftOccluders(leaf, elements_[s.index]);
        if (!hiding.empty() && !(radiometry(s).maxRadiosity > brightRadiosity)) {
          rayElements.push_back(s.index);
          continue;
        }
        exactLinks.push_back(index);
        occluders.push_back(std::move(hiding));
        exactFor[s.index] = int(id);
      }
    };
    int root = int(id);
    for (int e = int(id); e >= 0; e = elements_[e].parent) {
      collect(elementLinks[e]);
      root = e;
    }
    for (int c = rootCluster[root]; c >= 0; c = parentCluster[c]) collect(clusterLinks[c]);
    const std::vector<PolygonId>& partners = contacts_[leaf.polygon];

    SplitMix rng(options_.seed * 0x9e3779b97f4a7c15ull + id);
    std::vector<GatherEntry>& entries = gathered[id];
    constexpr double kPointWeight = 1.0 / 16;
    // The grandchild centres, nudged by a ten-thousandth of the leaf along two incommensurate
    // directions: subdivision puts them on round coordinates, where modelled features often
    // lie (a door's edge on a sideboard), and a point on the edge of a polygon in contact is
    // neither covered nor free: half its rays enter the door from its edge and meet back faces.
    const Vec3 nudge = (leaf.vertices[1] - leaf.vertices[0]) * 1.2345e-4 +
                       (leaf.vertices[leaf.vertexCount - 1] - leaf.vertices[0]) * 0.9876e-4;
    for (Vec3 x : leaf.grandchildCentres()) {
      x += nudge;
      if (isCovered(leaf.polygon, x)) {
        // x sees only the polygon covering it.
        if (const int h = coveringLeaf(leaf.polygon, x); h >= 0)
          entries.push_back({h, kPointWeight});
        continue;
      }
      double exactSum = 0;
      for (size_t j = 0; j < exactLinks.size(); ++j) {
        const Link& link = links_[exactLinks[j]];
        const Element& source = elements_[link.source.index];
        // A polygon in contact lies in x's plane: it sends x nothing unless it covers x (above).
        if (std::find(partners.begin(), partners.end(), source.polygon) != partners.end()) continue;
        const double f = unoccludedPointTransfer(link, x, leaf.normal, false);
        if (!(f > 0)) continue;
        const double visible =
            visibleTransfer(x, leaf.normal, leaf.polygon, source, occluders[j], f);
        if (visible > 0) entries.push_back({link.source.index, kPointWeight * visible});
        exactSum += visible;
      }
      const double remainder = 1 - exactSum;
      if (rayElements.empty() || !(remainder > 0)) continue;
      splitRemainder(leaf, x, remainder * kPointWeight, rayElements, exactFor, int(id), rng,
                     entries);
    }
    // One entry per element.
    std::sort(entries.begin(), entries.end(),
              [](const GatherEntry& a, const GatherEntry& b) { return a.element < b.element; });
    size_t merged = 0;
    for (size_t i = 0; i < entries.size(); ++i) {
      if (merged > 0 && entries[merged - 1].element == entries[i].element)
        entries[merged - 1].weight += entries[i].weight;
      else
        entries[merged++] = entries[i];
    }
    entries.resize(merged);
  }
  solveLeaves(gathered);
}

// What the exact sources leave of x's hemisphere, `remainder`, split by cosine-distributed rays
// among what they meet outside those sources: the leaf met (its radiosity), or nothing (a back
// face, or no surface). Rays are cast in rounds until a quarter of a round's count has met
// something outside the exact sources; where none does (the remainder is a sliver of the
// hemisphere) or the remainder is below kNoRays, it goes to the cluster sources' root elements
// in proportion to their unoccluded form factors from x.
void RadiositySolver::splitRemainder(const Element& leaf, const Vec3& x, double remainder,
                                     const std::vector<int>& rayElements,
                                     const std::vector<int>& exactFor, int leafId, SplitMix& rng,
                                     std::vector<GatherEntry>& entries) {
  constexpr double kNoRays = 1e-3 / 16;
  constexpr int kRounds = 8;
  constexpr double kSeam = 10;
  const int rays = std::max(0, options_.finalGatherRays);
  std::vector<int> met;
  if (rays > 0 && remainder > kNoRays) {
    const int side = std::max(1, int(std::lround(std::sqrt(double(rays)))));
    const Vec3 tangent = std::abs(leaf.normal.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const Vec3 u = normalize(cross(leaf.normal, tangent)), v = cross(leaf.normal, u);
    const auto isExact = [&](int h) {
      for (int e = h; e >= 0; e = elements_[e].parent)
        if (exactFor[e] == leafId) return true;
      return false;
    };
    for (int round = 0; round < kRounds && 4 * int(met.size()) < rays; ++round)
      for (int r = 0; r < rays; ++r) {
        // Stratified on the unit disc and lifted to the hemisphere (Malley's method).
        const int cell = r % (side * side);
        const double a = (cell % side + rng.uniform()) / side;
        const double phi = 2 * std::numbers::pi * (cell / side + rng.uniform()) / side;
        const double radius = std::sqrt(a);
        const Vec3 d = u * (radius * std::cos(phi)) + v * (radius * std::sin(phi)) +
                       leaf.normal * std::sqrt(std::max(0.0, 1 - a));
        ++stats_.finalGatherRays;
        // Polygons within the caster's epsilon of x are not met: a duplicate of the leaf's own
        // polygon (a double-modelled face) would be met at t = 0, from behind.
        const auto hit = rays_->intersect(x, d, rays_->epsilon(),
                                          std::numeric_limits<double>::infinity(), leaf.polygon);
        if (!hit) {
          ++stats_.finalGatherMisses;
          met.push_back(-1);
          continue;
        }
        const int h = leafAt(hit->polygon, hit->point);
        if (h >= 0 && isExact(h)) continue;
        const bool front = dot(scene_.polygons[hit->polygon].plane.normal, d) < 0;
        // A back face met right away is a seam the ray slipped into (x within the caster's
        // epsilon of a door's edge, whose bottom face it then does not meet), not a view of the
        // back of something: such rays say nothing.
        if (!front && hit->t < kSeam * rays_->epsilon()) continue;
        if (!front) ++stats_.finalGatherMisses;
        met.push_back(front ? h : -1);
      }
  }
  if (!met.empty()) {
    const double weight = remainder / double(met.size());
    for (int h : met)
      if (h >= 0) entries.push_back({h, weight});
    return;
  }
  std::vector<double> formFactors(rayElements.size());
  double total = 0;
  for (size_t k = 0; k < rayElements.size(); ++k)
    total += formFactors[k] = pointFormFactor(x, leaf.normal, elements_[rayElements[k]]);
  if (!(total > 0)) return;
  for (size_t k = 0; k < rayElements.size(); ++k)
    if (formFactors[k] > 0) entries.push_back({rayElements[k], remainder * formFactors[k] / total});
}

// Jacobi iteration over the leaves' point transfers, from the hierarchical solution: E_leaf =
// Σ weight x B(element), B_leaf = M + ρ E_leaf, inner elements' B the area mean of their leaves
// (children are stored after their parents, so one backward sweep pulls them up).
void RadiositySolver::solveLeaves(const std::vector<std::vector<GatherEntry>>& gathered) {
  const auto pull = [&](Rgb NodeRadiometry::*quantity) {
    for (size_t i = elements_.size(); i-- > 0;) {
      Element& e = elements_[i];
      if (e.isLeaf()) continue;
      Rgb sum;
      for (int k = 0; k < 4; ++k)
        sum += elements_[e.firstChild + k].radiometry.*quantity * elements_[e.firstChild + k].area;
      e.radiometry.*quantity = sum / e.area;
    }
  };
  for (size_t id = 0; id < elements_.size(); ++id)
    if (elements_[id].isLeaf()) {
      Rgb direct;
      for (const GatherEntry& g : gathered[id])
        direct += elements_[g.element].radiometry.emission * g.weight;
      elements_[id].radiometry.finalDirect = direct;
    }
  std::vector<Rgb> indirect(elements_.size());
  double scale = 1e-300;
  for (int iteration = 0; iteration < options_.maxIterations; ++iteration) {
    for (size_t id = 0; id < elements_.size(); ++id)
      if (elements_[id].isLeaf()) {
        Rgb sum;
        for (const GatherEntry& g : gathered[id])
          sum += elements_[g.element].radiometry.reflected * g.weight;
        indirect[id] = sum;
      }
    double largestChange = 0;
    for (size_t id = 0; id < elements_.size(); ++id) {
      Element& e = elements_[id];
      if (!e.isLeaf()) continue;
      NodeRadiometry& m = e.radiometry;
      m.finalIndirect = indirect[id];
      const Rgb b = m.emission + e.reflectance * (m.finalDirect + m.finalIndirect);
      const Rgb change = b - m.radiosity;
      largestChange =
          std::max({largestChange, std::abs(change.r), std::abs(change.g), std::abs(change.b)});
      scale = std::max(scale, b.maxComponent());
      m.radiosity = b;
      m.reflected = b - m.emission;
    }
    pull(&NodeRadiometry::radiosity);
    pull(&NodeRadiometry::reflected);
    stats_.finalIterations = iteration + 1;
    if (largestChange / scale < options_.convergence) break;
  }
}

}  // namespace penumbra
