// Link refinement (Hanrahan, Salzman & Aupperle 1991; clusters: Sillion 1995), keeping refined
// links as passive links (Drettakis & Sillion 1997) with their shafts (Haines & Wallace 1991).

#include "penumbra/radiosity/radiosity_solver.h"

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

namespace penumbra {

Shaft RadiositySolver::linkShaft(NodeRef receiver, NodeRef source) const {
  if (receiver.isCluster() || source.isCluster()) return Shaft(bounds(receiver), bounds(source));
  const Element& r = elements_[receiver.index];
  const Element& s = elements_[source.index];
  return Shaft(Polygon3(r.vertices.begin(), r.vertices.begin() + r.vertexCount),
               Polygon3(s.vertices.begin(), s.vertices.begin() + s.vertexCount));
}

int RadiositySolver::addLink(NodeRef receiver, NodeRef source, bool doEstimate, Shaft shaft) {
  Link link;
  link.receiver = receiver;
  link.source = source;
  if (doEstimate) estimate(link, nullptr, &shaft);
  if (options_.storeShafts) {
    link.shaft = int(shafts_.size());
    shafts_.push_back(shaft);
  }
  links_.push_back(std::move(link));
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
void RadiositySolver::refineLink(int index) {
  const NodeRef r = links_[index].receiver, s = links_[index].source;
  const bool selfLink = r == s;
  const bool overlapping =
      (r.isCluster() || s.isCluster()) && (selfLink || bounds(r).overlaps(bounds(s)));
  const bool splitR = canSplit(r), splitS = canSplit(s);
  if (!splitR && !splitS) return;
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
    if (!(power > options_.tolerance * totalPower_) && !clusterReceiverError) return;
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
  replaceLink(index, pairs);
}

// The link becomes passive; its children are the pairs that can exchange energy, each estimated
// (or left for refinement when a cluster end overlaps the other end) and refined in turn.
void RadiositySolver::replaceLink(int index,
                                  const std::vector<std::pair<NodeRef, NodeRef>>& pairs) {
  std::vector<int> children;
  for (const auto& [a, b] : pairs) {
    const bool bothElements = !a.isCluster() && !b.isCluster();
    if (bothElements && elements_[a.index].polygon == elements_[b.index].polygon) continue;
    // Nothing passes between a node entirely behind the other's element plane and that element.
    if (!a.isCluster()) {
      const Element& e = elements_[a.index];
      if (isBehind(b, Plane::fromPointNormal(e.vertices[0], e.normal))) continue;
    }
    if (!b.isCluster()) {
      const Element& e = elements_[b.index];
      if (isBehind(a, Plane::fromPointNormal(e.vertices[0], e.normal))) continue;
    }
    const bool mustRefine =
        (a.isCluster() || b.isCluster()) && (a == b || bounds(a).overlaps(bounds(b)));
    Link probe;
    probe.receiver = a;
    probe.source = b;
    PointTransfers pointValues;
    Shaft shaft = linkShaft(a, b);
    if (!mustRefine) {
      estimate(probe, &pointValues, &shaft);
      if (bothElements && probe.unoccludedTransfer <= 0) continue;
    }
    const int child = addLink(a, b, false, shaft);
    if (pointValues.valid) {
      if (pointTransfers_.size() <= size_t(child)) pointTransfers_.resize(links_.size());
      pointTransfers_[child] = pointValues;
    }
    links_[child].unoccludedTransfer = probe.unoccludedTransfer;
    links_[child].visibility = probe.visibility;
    links_[child].transferSpread = probe.transferSpread;
    links_[child].sourceSpread = probe.sourceSpread;
    links_[child].sourceShares = std::move(probe.sourceShares);
    links_[child].pointVisibleTransfers = std::move(probe.pointVisibleTransfers);
    children.push_back(child);
  }
  links_[index].active = false;
  links_[index].children = children;
  links_[index].sourceShares = {};
  links_[index].pointVisibleTransfers = {};
  for (int child : children) refineLink(child);
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
  std::vector<std::vector<int>> byReceiver(elements_.size());
  std::vector<int> pending;
  for (size_t i = 0; i < links_.size(); ++i)
    if (links_[i].active && !links_[i].receiver.isCluster()) {
      const int p = links_[i].receiver.index;
      if (byReceiver[p].empty()) pending.push_back(p);
      byReceiver[p].push_back(int(i));
    }
  bool refined = false;
  while (!pending.empty()) {
    const int p = pending.back();
    pending.pop_back();
    if (byReceiver[p].empty() || !canSplit({NodeRef::kElement, p})) continue;
    const Element receiver = elements_[p];
    std::array<Vec3, 16> points{};
    std::array<bool, 16> covered{};
    bool located = false;
    std::array<double, 16> sum{};
    for (int index : byReceiver[p]) {
      if (pointTransfers_.size() < links_.size()) pointTransfers_.resize(links_.size());
      PointTransfers& cached = pointTransfers_[index];
      if (!cached.valid || cached.unoccluded) {
        if (!located) {
          points = receiver.grandchildCentres();
          for (int k = 0; k < 16; ++k) covered[k] = isCovered(receiver.polygon, points[k]);
          located = true;
        }
      }
      if (cached.valid && cached.unoccluded) {
        // The quadrature's point form factors, as pointTransfer would compute them.
        const std::vector<float>& exact = links_[index].pointVisibleTransfers;
        for (int k = 0; k < 16; ++k)
          cached.values[k] =
              exact.size() == 16 ? exact[k]
              : covered[k]       ? 0.f
                           : float(double(cached.values[k]) * double(links_[index].visibility));
        cached.unoccluded = false;
      }
      if (!cached.valid) {
        const std::vector<float>& exact = links_[index].pointVisibleTransfers;
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
    if (!((*highest - *lowest) * receiver.area > options_.tolerance * totalPower_)) continue;
    refined = true;
    const std::vector<NodeRef> children = split({NodeRef::kElement, p});
    const size_t firstNew = links_.size();
    for (int index : byReceiver[p]) {
      std::vector<std::pair<NodeRef, NodeRef>> pairs;
      for (NodeRef c : children) pairs.push_back({c, links_[index].source});
      replaceLink(index, pairs);
    }
    byReceiver[p].clear();
    byReceiver.resize(elements_.size());
    for (size_t i = firstNew; i < links_.size(); ++i)
      if (links_[i].active && !links_[i].receiver.isCluster()) {
        const int q = links_[i].receiver.index;
        if (std::find(pending.begin(), pending.end(), q) == pending.end()) pending.push_back(q);
        byReceiver[q].push_back(int(i));
      }
  }
  return refined;
}

bool RadiositySolver::exceedsTolerance(NodeRef n, double irradianceError) const {
  return irradianceError * std::max(area(n), referenceArea_) > options_.tolerance * totalPower_;
}

bool RadiositySolver::refineActiveLinks() {
  const size_t before = links_.size();
  const size_t count = links_.size();
  for (size_t i = 0; i < count; ++i)
    if (links_[i].active) refineLink(int(i));
  return links_.size() != before;
}

}  // namespace penumbra
