// Verification of the line-space update: everything a pair's estimate reads, recomputed from the
// scene as it stands, and every pair estimated again, compared bit for bit with what is stored.

#include <cstring>
#include <sstream>

#include "penumbra/radiosity/face_contacts.h"
#include "penumbra/radiosity/galerkin/galerkin_internals.h"
#include "penumbra/radiosity/hierarchy_building.h"

namespace penumbra {

namespace {

template <typename T>
bool sameBits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

std::string describe(NodeRef n) {
  return std::string(n.isCluster() ? "cluster " : "element ") + std::to_string(n.index);
}

}  // namespace

std::string GalerkinRadiosity::verifyLinks() const {
  awaitShaftWork();
  std::ostringstream difference;
  // The hierarchy: element shapes from the polygons down, covers, cluster boxes and areas.
  std::vector<std::vector<int>> freshRoots;
  const std::vector<Element> roots = rootElements(scene_, freshRoots);
  for (size_t p = 0; p < freshRoots.size(); ++p) {
    if (freshRoots[p].size() != polygonRoots_[p].size())
      return "polygon " + std::to_string(p) + ": a different number of root elements";
    for (size_t k = 0; k < freshRoots[p].size(); ++k) {
      const Element& fresh = roots[freshRoots[p][k]];
      const GElement& e = elements_[polygonRoots_[p][k]];
      if (!sameBits(fresh.vertices, e.shape.vertices) || !sameBits(fresh.normal, e.shape.normal) ||
          fresh.area != e.area)
        return "polygon " + std::to_string(p) + ": root element " + std::to_string(k) +
               " is not where the polygon is";
    }
  }
  if (coveringPolygons(scene_) != contacts_)
    return "the stored covering polygons are not the scene's";
  for (size_t i = 0; i < elements_.size(); ++i) {
    const GElement& e = elements_[i];
    if (freshCover(e) != e.cover || coveredPointsOf(e) != e.coveredPoints)
      return "element " + std::to_string(i) + ": a stale cover";
    if (e.firstChild < 0) continue;
    const auto children = e.shape.childVertices();
    for (int c = 0; c < 4; ++c) {
      const GElement& child = elements_[e.firstChild + c];
      if (!sameBits(children[c], child.shape.vertices) ||
          elementArea(children[c], e.shape.vertexCount) != child.area)
        return "element " + std::to_string(e.firstChild + c) + " is not its parent's child";
    }
  }
  for (size_t c = 0; c < clusters_.size(); ++c) {
    const ClusterNode& cluster = clusters_[c].structure;
    const ClusterExtent extent = extentOf(cluster);
    if (!sameBits(extent.bounds.min, cluster.bounds.min) ||
        !sameBits(extent.bounds.max, cluster.bounds.max) || extent.area != cluster.area)
      return "cluster " + std::to_string(c) + ": a stale box or area";
  }

  // Every live pair from the root down, its candidates from its parent's recomputed ones.
  auto all = std::make_shared<std::vector<PolygonId>>(scene_.polygons.size());
  for (size_t i = 0; i < all->size(); ++i) (*all)[i] = PolygonId(i);
  std::vector<Candidates> candidates(links_.size());
  Counters counters;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    const GLink& link = links_[i];
    const Candidates& inherited = link.parent < 0 ? Candidates(all) : candidates[link.parent];
    const std::string pair = "pair " + std::to_string(i) + " (" + describe(link.receiver) +
                             " from " + describe(link.source) + ")";
    const bool exchanges = canExchange(link.receiver, link.source);
    if (link.state == GLink::kDropped) return pair + ": dropped, yet its parent's child";
    if (exchanges != (link.state != GLink::kNone))
      return pair + (exchanges ? ": exchanges light, stored as not" : ": cannot exchange light");
    if (link.state == GLink::kNone) continue;
    if (link.state == GLink::kSelf) {
      if ((link.candidates || !managed()) && (!link.candidates || *link.candidates != *inherited))
        return pair + ": a cluster's own pair with stale candidates";
      candidates[i] = inherited;
    } else {
      auto own = std::make_shared<const std::vector<PolygonId>>(
          shaftCandidates(link.receiver, link.source, *inherited));
      const Estimate e = estimate(link.receiver, link.source, CandidateView::of(*own), counters);
      if (!sameBits(e.k, link.k) || e.lobes != link.lobes ||
          float(e.meanTransfer) != link.meanTransfer || float(e.spread) != link.spread ||
          float(e.hiddenTransfer) != link.hiddenTransfer || e.hiddenPairs != link.hiddenPairs ||
          e.everyRay != link.everyRay) {
        difference.precision(17);
        difference << pair << ": stored K " << link.k[0] << ", " << link.k[4] << ", mean "
                   << link.meanTransfer << ", spread " << link.spread << ", hidden "
                   << link.hiddenTransfer << ", pairs " << link.hiddenPairs << ", every ray "
                   << link.everyRay << "; estimated again " << e.k[0] << ", " << e.k[4] << ", "
                   << float(e.meanTransfer) << ", " << float(e.spread) << ", "
                   << float(e.hiddenTransfer) << ", " << e.hiddenPairs << ", " << e.everyRay << " ("
                   << own->size() << " candidates)";
        return difference.str();
      }
      // Every estimated pair keeps its list under ShaftPolicy::kAll; a managed one may not.
      if ((link.candidates || !managed()) && (!link.candidates || *link.candidates != *own))
        return pair + ": stale candidates";
      if (link.candidateCount != own->size()) return pair + ": a stale candidate count";
      candidates[i] = own;
    }
    for (int c = link.firstChild; c < link.firstChild + link.childCount; ++c) {
      if (links_[c].parent != i) return "pair " + std::to_string(c) + ": a wrong parent";
      stack.push_back(c);
    }
  }
  if (std::string keys = verifyPassKeys(); !keys.empty()) return keys;
  return verifySolveState();
}

std::string GalerkinRadiosity::differenceFrom(const GalerkinRadiosity& other) const {
  const std::vector<GLink>&a = links(), &b = other.links();
  if (a.size() != b.size())
    return std::to_string(a.size()) + " pairs against " + std::to_string(b.size());
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].state != b[i].state || !(a[i].receiver == b[i].receiver) ||
        !(a[i].source == b[i].source) || !sameBits(a[i].k, b[i].k))
      return "pair " + std::to_string(i) + " (" + describe(a[i].receiver) + " from " +
             describe(a[i].source) + ")";
  if (elements_.size() != other.elements_.size())
    return std::to_string(elements_.size()) + " elements against " +
           std::to_string(other.elements_.size());
  for (size_t i = 0; i < elements_.size(); ++i)
    if (!sameBits(elements_[i].node.radiosity, other.elements_[i].node.radiosity))
      return "element " + std::to_string(i) + "'s radiosity";
  return {};
}

GalerkinRadiosity::PendingRefinement GalerkinRadiosity::pendingRefinement() const {
  awaitShaftWork();
  PendingRefinement pending;
  for (const GLink& link : links_) {
    if (asksToSplit(link)) ++pending.splits;
    if (link.state == GLink::kPassive && oracleOf(link) <= threshold_ * kCleanUpShare)
      ++pending.cleanUps;
  }
  return pending;
}

std::string GalerkinRadiosity::verifyPassKeys() const {
  for (size_t i = 0; i < passKeys_.size() && i < links_.size(); ++i) {
    if (passKeyStale_[i]) continue;
    const PassKey fresh = passKeyOf(links_[i]), &kept = passKeys_[i];
    if (fresh.state != kept.state || !sameBits(fresh.receiverArea, kept.receiverArea) ||
        !sameBits(fresh.variation, kept.variation) || !(fresh.source == kept.source))
      return "pair " + std::to_string(i) + ": the refinement pass's key is not the pair's";
  }
  return {};
}

}  // namespace penumbra
