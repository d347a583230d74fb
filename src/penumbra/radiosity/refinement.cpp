// Link refinement (Hanrahan, Salzman & Aupperle 1991; clusters: Sillion 1995), keeping refined
// links as passive links (Drettakis & Sillion 1997) with their shafts (Haines & Wallace 1991).

#include "penumbra/radiosity/radiosity_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>
#include <unordered_map>

#include "penumbra/base/check.h"
#include "penumbra/geometry/triangulation.h"
#include "penumbra/lighting/form_factor.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/receiver_locator.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

int RadiositySolver::addLink(NodeRef receiver, NodeRef source, bool doEstimate) {
  Link link;
  link.receiver = receiver;
  link.source = source;
  if (doEstimate) estimate(link);
  if (options_.storeShafts) {
    link.shaft = int(shafts_.size());
    shafts_.emplace_back(bounds(receiver), bounds(source));
  }
  links_.push_back(std::move(link));
  return int(links_.size()) - 1;
}

// A BF oracle on the error rather than on the transfer itself: refine while B_max(source) x (the
// form factor's variation over the receiver, plus the whole transfer when the source is partly
// hidden) — a bound on the irradiance error of the link anywhere on the receiver — exceeds
// tolerance x the largest emitted exitance. The bound is in irradiance, not in power, because a
// power bound lets small receivers keep large pointwise errors (and the furnace test sees them).
// Constant-element gathering is exact where the form factor is constant and the source fully
// visible, so those links need not be split however much power they carry; a cluster end has
// unknown variation, so its whole transfer counts. Clusters whose boxes overlap cannot be linked as
// wholes (their mutual form factor is meaningless), so such links are always refined.
void RadiositySolver::refineLink(int index) {
  const NodeRef r = links_[index].receiver, s = links_[index].source;
  const bool selfLink = r == s;
  const bool overlapping =
      (r.isCluster() || s.isCluster()) && (selfLink || bounds(r).overlaps(bounds(s)));
  const bool splitR = canSplit(r), splitS = canSplit(s);
  if (!splitR && !splitS) return;
  if (!overlapping) {
    const Link& link = links_[index];
    const bool partlyVisible = link.visibility > 0 && link.visibility < 1;
    const double error =
        (double(link.transferSpread) + (partlyVisible ? double(link.unoccludedTransfer) : 0)) *
        radiometry(s).maxRadiosity * area(r);
    if (!(error > options_.tolerance * totalPower_)) return;
  }
  std::vector<std::pair<NodeRef, NodeRef>> pairs;
  if (selfLink) {
    for (NodeRef a : split(r))
      for (NodeRef b : clusters_[r.index].children)
        if (!(a == b && !a.isCluster())) pairs.push_back({a, b});
  } else {
    // Split the larger end (clusters before elements of the same size), as far as allowed.
    const bool splitReceiver =
        splitR && (!splitS || size(r) + (r.isCluster() ? 1e-12 : 0) >= size(s));
    if (splitReceiver)
      for (NodeRef a : split(r)) pairs.push_back({a, s});
    else
      for (NodeRef b : split(s)) pairs.push_back({r, b});
  }
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
    if (!mustRefine) {
      estimate(probe);
      if (bothElements && probe.unoccludedTransfer <= 0) continue;
    }
    const int child = addLink(a, b, false);
    links_[child].unoccludedTransfer = probe.unoccludedTransfer;
    links_[child].visibility = probe.visibility;
    links_[child].transferSpread = probe.transferSpread;
    children.push_back(child);
  }
  links_[index].active = false;
  links_[index].children = children;
  for (int child : children) refineLink(child);
}

bool RadiositySolver::refineActiveLinks() {
  const size_t before = links_.size();
  const size_t count = links_.size();
  for (size_t i = 0; i < count; ++i)
    if (links_[i].active) refineLink(int(i));
  return links_.size() != before;
}

}  // namespace penumbra
