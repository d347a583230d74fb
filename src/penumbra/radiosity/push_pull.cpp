// Push-pull (Hanrahan, Salzman & Aupperle 1991): irradiance gathered at a node is pushed to the
// leaves, radiosity is pulled back up as area means (exact, since children tile their parent).

#include "penumbra/radiosity/radiosity_solver.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

void RadiositySolver::pullEmission(NodeRef node) {
  NodeRadiometry& m = radiometry(node);
  if (!node.isCluster() && elements_[node.index].isLeaf()) {
    m.radiosity = m.emission;
    m.reflected = Rgb{};
    m.maxRadiosity = m.emission.maxComponent();
    m.minRadiosity = std::min({m.emission.r, m.emission.g, m.emission.b});
    return;
  }
  const std::vector<NodeRef> children =
      node.isCluster()
          ? clusters_[node.index].children
          : std::vector<NodeRef>{{NodeRef::kElement, elements_[node.index].firstChild}};
  Rgb emission;
  double maxRadiosity = 0, minRadiosity = 1e300;
  for (NodeRef c : children) {
    pullEmission(c);
    emission += radiometry(c).emission * area(c);
    maxRadiosity = std::max(maxRadiosity, radiometry(c).maxRadiosity);
    minRadiosity = std::min(minRadiosity, radiometry(c).minRadiosity);
  }
  NodeRadiometry& pulled = radiometry(node);
  pulled.emission = emission / area(node);
  pulled.radiosity = pulled.emission;
  pulled.reflected = Rgb{};
  pulled.maxRadiosity = maxRadiosity;
  pulled.minRadiosity = minRadiosity;
}

// Push irradiance down to the leaves, compute B there, pull area means back up (Hanrahan et al.).
void RadiositySolver::pushPull(NodeRef node, const Rgb& direct, const Rgb& indirect,
                               double& largestChange) {
  Rgb eDirect, eIndirect;
  {
    NodeRadiometry& m = radiometry(node);
    eDirect = direct + m.gatheredDirect;
    eIndirect = indirect + m.gatheredIndirect;
    m.irradianceDirect = eDirect;
    m.irradianceIndirect = eIndirect;
  }
  if (!node.isCluster() && elements_[node.index].isLeaf()) {
    Element& e = elements_[node.index];
    NodeRadiometry& m = e.radiometry;
    const Rgb b = m.emission + e.reflectance * (eDirect + eIndirect);
    const Rgb change = b - m.radiosity;
    largestChange =
        std::max({largestChange, std::abs(change.r), std::abs(change.g), std::abs(change.b)});
    m.radiosity = b;
    m.reflected = b - m.emission;
    m.maxRadiosity = b.maxComponent();
    m.minRadiosity = std::min({b.r, b.g, b.b});
    return;
  }
  Rgb b, reflected;
  double maxRadiosity = 0, minRadiosity = 1e300;
  const auto visit = [&](NodeRef c) {
    pushPull(c, eDirect, eIndirect, largestChange);
    const NodeRadiometry& cm = radiometry(c);
    b += cm.radiosity * area(c);
    reflected += cm.reflected * area(c);
    maxRadiosity = std::max(maxRadiosity, cm.maxRadiosity);
    minRadiosity = std::min(minRadiosity, cm.minRadiosity);
  };
  if (node.isCluster()) {
    const size_t count = clusters_[node.index].children.size();
    for (size_t i = 0; i < count; ++i) visit(clusters_[node.index].children[i]);
  } else {
    const int first = elements_[node.index].firstChild;
    for (int k = 0; k < 4; ++k) visit({NodeRef::kElement, first + k});
  }
  NodeRadiometry& m = radiometry(node);
  m.radiosity = b / area(node);
  m.reflected = reflected / area(node);
  m.maxRadiosity = maxRadiosity;
  m.minRadiosity = minRadiosity;
}

}  // namespace penumbra
