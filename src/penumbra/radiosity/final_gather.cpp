// Final gather (Smits, Arvo & Greenberg 1994; Lischinski, Tampieri & Greenberg 1993): the
// irradiance shown at a leaf, re-gathered from every active link above it at the leaf's own points.
//
// Gathering hands a receiver the mean of what its links bring, and push-pull hands that mean on
// to every leaf below: a wall element linked as a whole to the part of another wall 1 cm in front
// of half of it passes half a hemisphere to each of its leaves, where one half sees all of it and
// the other none; a cluster receiver passes the same irradiance to a chair's seat and to the
// underside of that seat. The power oracle lets such a mean stand wherever it carries little
// power (a small receiver, a small cluster), so the leaves' irradiance strays by tens of percent
// where the energy balance is exact. The final gather keeps the solution (B) and re-evaluates
// each link above a leaf at the leaf's 16 grandchild centres: the exact point-to-source form
// factor there times the link's visibility and the source's radiosity. Links on the leaf itself
// keep their transfer, the adaptive quadrature's mean over exactly this leaf.

#include <array>
#include <vector>

#include "penumbra/radiosity/radiosity_solver.h"

namespace penumbra {

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

  for (size_t id = 0; id < elements_.size(); ++id) {
    Element& leaf = elements_[id];
    if (!leaf.isLeaf()) continue;
    Rgb direct, indirect;
    for (int index : elementLinks[id]) {
      const Link& link = links_[index];
      direct += sourceValue(link, &NodeRadiometry::emission) * link.transfer();
      indirect += sourceValue(link, &NodeRadiometry::reflected) * link.transfer();
    }
    const std::array<Vec3, 16> points = leaf.grandchildCentres();
    std::array<bool, 16> covered{};
    for (int k = 0; k < 16; ++k) covered[k] = isCovered(leaf.polygon, points[k]);
    const auto gather = [&](const std::vector<int>& links, const auto& visibilityAt) {
      for (int index : links) {
        const Link& link = links_[index];
        double transfer = 0;
        for (int k = 0; k < 16; ++k)
          transfer += unoccludedPointTransfer(link, points[k], leaf.normal, covered[k]) *
                      visibilityAt(link, k);
        transfer /= 16;
        direct += sourceValue(link, &NodeRadiometry::emission) * transfer;
        indirect += sourceValue(link, &NodeRadiometry::reflected) * transfer;
      }
    };
    // The quadtree path from the leaf up: childPath[d] is which child of its parent the ancestor
    // (or the leaf) at depth d + 1 is.
    std::vector<int> childPath(leaf.depth);
    int root = int(id);
    for (int e = int(id); elements_[e].parent >= 0; e = elements_[e].parent) {
      const int parent = elements_[e].parent;
      childPath[elements_[e].depth - 1] = e - elements_[parent].firstChild;
      root = parent;
    }
    for (int e = leaf.parent; e >= 0; e = elements_[e].parent) {
      const Element& ancestor = elements_[e];
      // The ancestor's grandchild cell holding the leaf's point k (k = 4 × child + grandchild of
      // the leaf): the next two steps of the path down from the ancestor, completed by k's.
      const auto cellOf = [&](int k) {
        const int below = leaf.depth - ancestor.depth;
        const int first = childPath[ancestor.depth];
        const int second = below >= 2 ? childPath[ancestor.depth + 1] : k / 4;
        return 4 * first + second;
      };
      std::array<Vec3, 16> cellCentres{};
      bool located = false;
      gather(elementLinks[e], [&](const Link& link, int k) -> double {
        if (link.pointVisibleTransfers.size() != 16) return link.visibility;
        // Exact visibility known at the ancestor's 16 grandchild centres: the leaf's point takes
        // the visible fraction of its cell, not the mean over the ancestor.
        if (!located) cellCentres = ancestor.grandchildCentres(), located = true;
        const int cell = cellOf(k);
        const double f = unoccludedPointTransfer(link, cellCentres[cell], ancestor.normal, false);
        return f > 0 ? std::min(1.0, double(link.pointVisibleTransfers[cell]) / f)
                     : link.visibility;
      });
    }
    const auto meanVisibility = [](const Link& link, int) { return double(link.visibility); };
    for (int c = rootCluster[root]; c >= 0; c = parentCluster[c])
      gather(clusterLinks[c], meanVisibility);
    leaf.radiometry.finalDirect = direct;
    leaf.radiometry.finalIndirect = indirect;
  }
}

}  // namespace penumbra
