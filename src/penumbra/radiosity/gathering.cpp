// Gathering over the active links (Hanrahan, Salzman & Aupperle 1991), Jacobi iteration.

#include "penumbra/radiosity/radiosity_solver.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

Rgb RadiositySolver::sourceValue(const Link& link, Rgb NodeRadiometry::*quantity) const {
  if (link.sourceShares.empty()) return radiometry(link.source).*quantity;
  Rgb value;
  if (!link.source.isCluster()) {
    const Element& e = elements_[link.source.index];
    if (e.isLeaf()) return e.radiometry.*quantity;
    for (int q = 0; q < 4; ++q) {
      const Element& child = elements_[e.firstChild + q];
      for (int g = 0; g < 4; ++g)
        value += (child.isLeaf() ? child : elements_[child.firstChild + g]).radiometry.*quantity *
                 double(link.sourceShares[4 * q + g]);
    }
    return value;
  }
  const Cluster& c = clusters_[link.source.index];
  for (int i = c.elementBegin; i < c.elementEnd; ++i)
    value += elements_[rootOrder_[i]].radiometry.*quantity *
             double(link.sourceShares[i - c.elementBegin]);
  return value;
}

// Jacobi gathering over the active links. The direct part depends on emission only, so it is
// gathered once; the indirect part is iterated to convergence.
void RadiositySolver::solve() {
  for (Element& e : elements_) e.radiometry.gatheredDirect = e.radiometry.gatheredIndirect = {};
  for (Cluster& c : clusters_) c.radiometry.gatheredDirect = c.radiometry.gatheredIndirect = {};
  for (const Link& link : links_)
    if (link.active)
      radiometry(link.receiver).gatheredDirect +=
          sourceValue(link, &NodeRadiometry::emission) * link.transfer();
  stats_.iterations = 0;
  for (int iteration = 0; iteration < options_.maxIterations; ++iteration) {
    for (Element& e : elements_) e.radiometry.gatheredIndirect = {};
    for (Cluster& c : clusters_) c.radiometry.gatheredIndirect = {};
    for (const Link& link : links_)
      if (link.active)
        radiometry(link.receiver).gatheredIndirect +=
            sourceValue(link, &NodeRadiometry::reflected) * link.transfer();
    double largestChange = 0;
    pushPull({NodeRef::kCluster, 0}, {}, {}, largestChange);
    stats_.iterations = iteration + 1;
    const double scale = std::max(clusters_[0].radiometry.maxRadiosity, 1e-300);
    stats_.residual = largestChange / scale;
    if (stats_.residual < options_.convergence) break;
  }
  stats_.converged = stats_.residual < options_.convergence;
}

}  // namespace penumbra
