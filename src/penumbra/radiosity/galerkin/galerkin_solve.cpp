// Galerkin solving: Jacobi gathering over the active links and push-pull through the hierarchy.
// Push restricts a parent's linear function to each child exactly; pull projects the children's
// functions onto the parent's basis (an area-weighted sum): neither creates nor loses energy.

#include <algorithm>
#include <cmath>

#include "penumbra/radiosity/galerkin/galerkin_internals.h"

namespace penumbra {

namespace {

// The largest value over the element of a linear function's channels (mean plus how far the
// linear part can reach), for the oracle's B_max.
double upperBound(const LinearRgb& c, double reach) {
  const auto channel = [&](double Rgb::*k) {
    return c[0].*k + reach * (std::abs(c[1].*k) + std::abs(c[2].*k));
  };
  return std::max({channel(&Rgb::r), channel(&Rgb::g), channel(&Rgb::b)});
}

}  // namespace

void GalerkinRadiosity::pullEmission(NodeRef n) {
  Node& node = nodeOf(n);
  if (n.isElement()) {
    const GElement& e = elements_[n.index];
    node.radiosity = {node.emission, Rgb{}, Rgb{}};
    node.maxRadiosity = node.emission.maxComponent();
    node.maxReflectance = e.reflectance.maxComponent();
    return;
  }
  const ClusterNode& cluster = clusters_[n.index].structure;
  Rgb emission;
  double maxRadiosity = 0, maxReflectance = 0;
  for (NodeRef child : cluster.children) {
    pullEmission(child);
    const Node& c = nodeOf(child);
    emission += c.emission * area(child);
    maxRadiosity = std::max(maxRadiosity, c.maxRadiosity);
    maxReflectance = std::max(maxReflectance, c.maxReflectance);
  }
  Node& again = nodeOf(n);  // children recursed; clusters_ does not grow, but stay explicit
  again.emission = cluster.area > 0 ? emission / cluster.area : Rgb{};
  again.radiosity = {again.emission, Rgb{}, Rgb{}};
  again.maxRadiosity = maxRadiosity;
  again.maxReflectance = maxReflectance;
}

void GalerkinRadiosity::solve() {
  for (int iteration = 0; iteration < options_.maxIterations; ++iteration) {
    for (GElement& e : elements_) e.node.gatheredDirect = e.node.gatheredIndirect = {};
    for (GCluster& c : clusters_) c.node.gatheredDirect = c.node.gatheredIndirect = {};
    for (const GLink& link : links_) {
      if (!link.active) continue;
      const Node& source = nodeOf(link.source);
      const LinearRgb emitted{source.emission, Rgb{}, Rgb{}};
      LinearRgb reflected = source.radiosity;
      reflected[0] = reflected[0] - source.emission;
      Node& receiver = nodeOf(link.receiver);
      const int rows = link.receiver.isCluster() ? 1 : 3;
      const int columns = link.source.isCluster() ? 1 : 3;
      for (int beta = 0; beta < rows; ++beta)
        for (int alpha = 0; alpha < columns; ++alpha) {
          const double k = link.k[beta * 3 + alpha];
          receiver.gatheredDirect[beta] += emitted[alpha] * k;
          receiver.gatheredIndirect[beta] += reflected[alpha] * k;
        }
    }
    const double change = pushPull({NodeRef::kCluster, 0}, {}, {});
    ++stats_.iterations;
    // Against the largest reflected radiosity, not B: a lamp's emission can be a hundred times
    // what the walls reflect, and measured against it the indirect light stopped 1% short.
    double reflected = 0;
    for (const GElement& e : elements_)
      if (e.isLeaf())
        reflected = std::max(reflected, (e.node.radiosity[0] - e.node.emission).maxComponent());
    if (change <= options_.convergence * std::max(reflected, 1e-300)) break;
  }
}

double GalerkinRadiosity::pushPull(NodeRef n, const LinearRgb& direct, const LinearRgb& indirect) {
  if (n.isCluster()) {
    GCluster& cluster = clusters_[n.index];
    const Rgb d = direct[0] + cluster.node.gatheredDirect[0];
    const Rgb i = indirect[0] + cluster.node.gatheredIndirect[0];
    cluster.node.irradianceDirect = {d, Rgb{}, Rgb{}};
    cluster.node.irradianceIndirect = {i, Rgb{}, Rgb{}};
    double change = 0, maxRadiosity = 0;
    Rgb radiosity;
    for (NodeRef child : cluster.structure.children) {
      change = std::max(change, pushPull(child, {d, Rgb{}, Rgb{}}, {i, Rgb{}, Rgb{}}));
      const Node& c = nodeOf(child);
      radiosity += c.radiosity[0] * area(child);
      maxRadiosity = std::max(maxRadiosity, c.maxRadiosity);
    }
    cluster.node.radiosity = {
        cluster.structure.area > 0 ? radiosity / cluster.structure.area : Rgb{}, Rgb{}, Rgb{}};
    cluster.node.maxRadiosity = maxRadiosity;
    return change;
  }
  GElement& e = elements_[n.index];
  LinearRgb d, i;
  for (int k = 0; k < 3; ++k) {
    d[k] = direct[k] + e.node.gatheredDirect[k];
    i[k] = indirect[k] + e.node.gatheredIndirect[k];
  }
  e.node.irradianceDirect = d;
  e.node.irradianceIndirect = i;
  if (e.isLeaf()) {
    LinearRgb b;
    for (int k = 0; k < 3; ++k) b[k] = e.reflectance * (d[k] + i[k]);
    b[0] += e.node.emission;
    double change = 0;
    for (int k = 0; k < 3; ++k)
      change = std::max(change, (b[k] - e.node.radiosity[k]).maxComponent());
    for (int k = 0; k < 3; ++k)
      change = std::max(change, (e.node.radiosity[k] - b[k]).maxComponent());
    e.node.radiosity = b;
    e.node.maxRadiosity = upperBound(b, e.basis.reach());
    return change;
  }
  const int first = e.firstChild;
  const double parentArea = e.area;
  double change = 0, maxRadiosity = 0;
  LinearRgb pulled{};
  for (int c = first; c < first + 4; ++c) {
    const BasisTransfer t = elements_[c].fromParent;
    LinearRgb childD{}, childI{};
    for (int alpha = 0; alpha < 3; ++alpha)
      for (int beta = 0; beta < 3; ++beta) {
        childD[alpha] += d[beta] * t[beta][alpha];
        childI[alpha] += i[beta] * t[beta][alpha];
      }
    change = std::max(change, pushPull({NodeRef::kElement, c}, childD, childI));
    const GElement& child = elements_[c];
    const double share = child.area / parentArea;
    for (int beta = 0; beta < 3; ++beta)
      for (int alpha = 0; alpha < 3; ++alpha)
        pulled[beta] += child.node.radiosity[alpha] * (share * t[beta][alpha]);
    maxRadiosity = std::max(maxRadiosity, child.node.maxRadiosity);
  }
  elements_[n.index].node.radiosity = pulled;
  elements_[n.index].node.maxRadiosity = maxRadiosity;
  return change;
}

}  // namespace penumbra
