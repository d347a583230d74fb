// Link refinement (Hanrahan, Salzman & Aupperle 1991; clusters: Sillion 1995), keeping refined
// links as passive links (Drettakis & Sillion 1997) with their shafts (Haines & Wallace 1991).

#include "penumbra/radiosity/radiosity_solver.h"

#include <algorithm>
#include <array>
#include <optional>
#include <utility>
#include <vector>

#include "penumbra/base/input_error.h"
#include "penumbra/base/parallel_for.h"

namespace penumbra {

Shaft RadiositySolver::linkShaft(NodeRef receiver, NodeRef source) const {
  if (receiver.isCluster() || source.isCluster()) return Shaft(bounds(receiver), bounds(source));
  const Element& r = elements_[receiver.index];
  const Element& s = elements_[source.index];
  return Shaft(Polygon3(r.vertices.begin(), r.vertices.begin() + r.vertexCount),
               Polygon3(s.vertices.begin(), s.vertices.begin() + s.vertexCount));
}

int RadiositySolver::addLink(const Link& link, const std::optional<Shaft>& shaft) {
  links_.push_back(link);
  if (options_.storeShafts) {
    links_.back().shaft = int(shafts_.size());
    shafts_.push_back(shaft ? *shaft : linkShaft(link.receiver, link.source));
  }
  return int(links_.size()) - 1;
}

// The link oracle, a BF oracle on power (Hanrahan, Salzman & Aupperle 1991): refine while
// B_max(source) x A_receiver x (what the link cannot represent) exceeds tolerance x the emitted
// power of the scene. What a link cannot represent, counted as the whole unoccluded transfer:
// visibility when the source is partly hidden (it varies over the receiver). The variation of an
// element receiver's form factor is left to the receiver oracle (refineReceivers), which sees
// the sum over the receiver's links, where variations of links to sources on different sides
// cancel. A cluster receiver gives all its surfaces the same irradiance whatever their
// orientation, cover (a chair leg's foot on the floor) or visibility, so its whole transfer may
// be misplaced at every point of it: that error is weighed as an irradiance (exceedsTolerance),
// and such links are refined at the receiver, which splitting the source does not mend. (Before,
// the larger end was split: a chair cluster kept receiving from ever smaller pieces of the walls,
// and its leaves strayed from 5% to 230% of the furnace irradiance.) Clusters whose boxes overlap
// cannot be linked as wholes (their mutual form factor is meaningless), so such links are always
// refined.
std::optional<std::vector<std::pair<NodeRef, NodeRef>>> RadiositySolver::refinementOf(int index) {
  const NodeRef r = links_[index].receiver, s = links_[index].source;
  const bool selfLink = r == s;
  const bool overlapping =
      (r.isCluster() || s.isCluster()) && (selfLink || bounds(r).overlaps(bounds(s)));
  const bool splitR = canSplit(r), splitS = canSplit(s);
  if (!splitR && !splitS) return std::nullopt;
  if (!overlapping) {
    const Link& link = links_[index];
    const NodeRadiometry& b = radiometry(s);
    const double transfer = double(link.unoccludedTransfer);
    const bool partlyVisible = link.visibility > 0 && link.visibility < 1;
    const double power =
        std::max((partlyVisible ? 1 : 0) * transfer * area(r) * b.maxRadiosity,
                 double(link.sourceSpread) * area(s) * (b.maxRadiosity - b.minRadiosity));
    // A cluster receiver hands all its surfaces the same irradiance whatever their orientation,
    // cover or visibility: the whole transfer may be misplaced, at every point of the cluster.
    const bool clusterReceiverError =
        r.isCluster() && exceedsTolerance(r, transfer * b.maxRadiosity);
    if (!(power > options_.tolerance * totalPower_) && !clusterReceiverError) return std::nullopt;
  }
  std::vector<std::pair<NodeRef, NodeRef>> pairs;
  if (selfLink) {
    for (NodeRef a : split(r))
      for (NodeRef b : clusters_[r.index].children)
        if (!(a == b && !a.isCluster())) pairs.push_back({a, b});
  } else {
    // Split the larger end, as far as allowed; a cluster receiver always (what it cannot
    // represent, its surfaces' different orientations, splitting the source does not mend).
    const bool splitReceiver = splitR && (!splitS || r.isCluster() || size(r) >= size(s));
    if (splitReceiver)
      for (NodeRef a : split(r)) pairs.push_back({a, s});
    else
      for (NodeRef b : split(s)) pairs.push_back({r, b});
  }
  return pairs;
}

// Each link becomes passive; its children are the pairs that can exchange energy, each estimated
// (or left for refinement when a cluster end overlaps the other end). The pairs are filtered in
// order, estimated in parallel (estimate reads the hierarchy only; nothing is split meanwhile)
// and appended in order.
std::vector<int> RadiositySolver::replaceLinks(
    const std::vector<std::pair<int, std::vector<std::pair<NodeRef, NodeRef>>>>& replacements) {
  struct Candidate {
    int parent = 0;
    bool mustRefine = false;
    Link link;
    std::optional<Shaft> shaft;  // built when the estimate or storage needs it
    PointTransfers pointValues;
    EstimateCounters counters;
  };
  // Two elements that exchange nothing get no link.
  const auto isDiscarded = [](const Candidate& c) {
    return !c.mustRefine && !c.link.receiver.isCluster() && !c.link.source.isCluster() &&
           c.link.unoccludedTransfer <= 0;
  };
  std::vector<Candidate> candidates;
  for (const auto& [index, pairs] : replacements)
    for (const auto& [a, b] : pairs) {
      const bool bothElements = !a.isCluster() && !b.isCluster();
      if (bothElements && elements_[a.index].polygon == elements_[b.index].polygon) continue;
      // Nothing passes between a node entirely behind the other's element plane and that element.
      if (!a.isCluster() && isBehind(b, elements_[a.index])) continue;
      if (!b.isCluster() && isBehind(a, elements_[b.index])) continue;
      Candidate& c = candidates.emplace_back();
      c.parent = index;
      c.mustRefine = (a.isCluster() || b.isCluster()) && (a == b || bounds(a).overlaps(bounds(b)));
      c.link.receiver = a;
      c.link.source = b;
    }
  if ((long long)(links_.size() + candidates.size()) > options_.maxLinks)
    throw budgetExceeded("links", options_.maxLinks);
  parallelFor((long long)candidates.size(), options_.threads, [&](long long i) {
    Candidate& c = candidates[i];
    if (!c.mustRefine) estimate(c.link, c.counters, &c.pointValues, &c.shaft);
    if (options_.storeShafts && !c.shaft && !isDiscarded(c))
      c.shaft = linkShaft(c.link.receiver, c.link.source);
  });
  std::vector<int> added;
  size_t next = 0;
  for (const auto& [index, pairs] : replacements) {
    std::vector<int> children;
    for (; next < candidates.size() && candidates[next].parent == index; ++next) {
      Candidate& c = candidates[next];
      stats_.visibilityRays += c.counters.visibilityRays;
      stats_.unoccludedByShaft += c.counters.unoccludedByShaft;
      stats_.exactVisibilityPoints += c.counters.exactVisibilityPoints;
      if (isDiscarded(c)) continue;
      const int child = addLink(c.link, c.shaft);
      if (c.pointValues.valid) {
        if (pointTransfers_.size() < links_.size()) pointTransfers_.resize(links_.size());
        pointTransfers_[child] = c.pointValues;
      }
      children.push_back(child);
    }
    Link& link = links_[index];
    link.active = false;
    link.children = children;
    link.sourceShares = {};
    link.pointVisibleTransfers = {};
    added.insert(added.end(), children.begin(), children.end());
  }
  return added;
}

void RadiositySolver::refineInWaves(std::vector<int> wave) {
  while (!wave.empty()) {
    std::vector<std::pair<int, std::vector<std::pair<NodeRef, NodeRef>>>> replacements;
    for (int index : wave)
      if (auto pairs = refinementOf(index)) replacements.push_back({index, std::move(*pairs)});
    wave = replaceLinks(replacements);
  }
}

// Receiver refinement. Gathering hands every part of a receiver the mean of what its links bring,
// so the irradiance error on the receiver is the variation over it of the sum of its links'
// point-to-source transfers times B, not the sum of each link's variation: links to sources on
// all sides vary in opposite ways and cancel (a receiver linked to everything it sees at one
// level gets exactly the right irradiance in a furnace, however much each link varies), while
// links at mixed levels leave a variation that no single link shows. So, per element receiver:
// the spread of Σ_links F(x, source) V B_source over its 16 grandchild centres, times its area,
// against the same power threshold as links; where it is exceeded, all the receiver's links
// move down to its children.
bool RadiositySolver::refineReceivers() {
  std::vector<int> pending;  // receivers to examine, in increasing order
  {
    std::vector<char> seen(elements_.size(), 0);
    for (const Link& link : links_)
      if (link.active && !link.receiver.isCluster() && !seen[link.receiver.index]) {
        seen[link.receiver.index] = 1;
        pending.push_back(link.receiver.index);
      }
    std::sort(pending.begin(), pending.end());
  }
  bool refined = false;
  while (!pending.empty()) {
    // Each pending receiver's active links, in link order.
    std::vector<int> slot(elements_.size(), -1);
    for (size_t k = 0; k < pending.size(); ++k) slot[pending[k]] = int(k);
    std::vector<std::vector<int>> byReceiver(pending.size());
    for (size_t i = 0; i < links_.size(); ++i)
      if (links_[i].active && !links_[i].receiver.isCluster())
        if (const int k = slot[links_[i].receiver.index]; k >= 0) byReceiver[k].push_back(int(i));
    // The oracle, receiver by receiver in parallel (each writes only its own links' cache).
    if (pointTransfers_.size() < links_.size()) pointTransfers_.resize(links_.size());
    std::vector<char> splitting(pending.size(), 0);
    parallelFor((long long)pending.size(), options_.threads, [&](long long k) {
      const int p = pending[k];
      if (byReceiver[k].empty() || !canSplit({NodeRef::kElement, p})) return;
      splitting[k] = receiverNeedsSplit(p, byReceiver[k]) ? 1 : 0;
    });
    std::vector<std::pair<int, std::vector<std::pair<NodeRef, NodeRef>>>> replacements;
    for (size_t k = 0; k < pending.size(); ++k) {
      if (!splitting[k]) continue;
      refined = true;
      const std::vector<NodeRef> children = split({NodeRef::kElement, pending[k]});
      for (int index : byReceiver[k]) {
        std::vector<std::pair<NodeRef, NodeRef>> pairs;
        for (NodeRef c : children) pairs.push_back({c, links_[index].source});
        replacements.push_back({index, std::move(pairs)});
      }
    }
    // The receivers' new links, refined by the link oracle; then every element receiver that
    // got a link is examined again.
    const size_t firstNew = links_.size();
    refineInWaves(replaceLinks(replacements));
    std::vector<char> seen(elements_.size(), 0);
    pending.clear();
    for (size_t i = firstNew; i < links_.size(); ++i)
      if (links_[i].active && !links_[i].receiver.isCluster() && !seen[links_[i].receiver.index]) {
        seen[links_[i].receiver.index] = 1;
        pending.push_back(links_[i].receiver.index);
      }
    std::sort(pending.begin(), pending.end());
  }
  return refined;
}

// The receiver oracle for receiver p with its active links (their point transfers cached).
bool RadiositySolver::receiverNeedsSplit(int p, const std::vector<int>& links) {
  const Element& receiver = elements_[p];
  std::array<Vec3, 16> points{};
  std::array<bool, 16> covered{};
  bool located = false;
  std::array<double, 16> sum{};
  for (int index : links) {
    PointTransfers& cached = pointTransfers_[index];
    if ((!cached.valid || cached.unoccluded) && !located) {
      points = receiver.grandchildCentres();
      for (int k = 0; k < 16; ++k) covered[k] = isCovered(receiver.polygon, points[k]);
      located = true;
    }
    const std::vector<float>& exact = links_[index].pointVisibleTransfers;
    if (cached.valid && cached.unoccluded) {
      // The quadrature's point form factors, as pointTransfer would compute them.
      for (int k = 0; k < 16; ++k)
        cached.values[k] = exact.size() == 16 ? exact[k]
                           : covered[k]
                               ? 0.f
                               : float(double(cached.values[k]) * double(links_[index].visibility));
      cached.unoccluded = false;
    }
    if (!cached.valid) {
      for (int k = 0; k < 16; ++k)
        cached.values[k] =
            exact.size() == 16
                ? exact[k]
                : float(pointTransfer(links_[index], points[k], receiver.normal, covered[k]));
      cached.valid = true;
    }
    const double b = sourceValue(links_[index], &NodeRadiometry::radiosity).maxComponent();
    for (int k = 0; k < 16; ++k) sum[k] += cached.values[k] * b;
  }
  const auto [lowest, highest] = std::minmax_element(sum.begin(), sum.end());
  return (*highest - *lowest) * receiver.area > options_.tolerance * totalPower_;
}

bool RadiositySolver::exceedsTolerance(NodeRef n, double irradianceError) const {
  return irradianceError * std::max(area(n), referenceArea_) > options_.tolerance * totalPower_;
}

bool RadiositySolver::refineActiveLinks() {
  const size_t before = links_.size();
  std::vector<int> active;
  for (size_t i = 0; i < links_.size(); ++i)
    if (links_[i].active) active.push_back(int(i));
  refineInWaves(std::move(active));
  return links_.size() != before;
}

}  // namespace penumbra
