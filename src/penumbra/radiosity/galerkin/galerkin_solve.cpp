// Galerkin solving: Jacobi gathering over the active links and push-pull through the hierarchy.
// Push restricts a parent's linear function to each child exactly; pull projects the children's
// functions onto the parent's basis (an area-weighted sum): neither creates nor loses energy.

#include <algorithm>
#include <cmath>

#include "penumbra/radiosity/galerkin/axis_lobes.h"
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
  if (n.isElement()) {
    GElement& e = elements_[n.index];
    e.node.radiosity = {e.node.emission, Rgb{}, Rgb{}};
    e.node.maxRadiosity = e.node.emission.maxComponent();
    e.node.maxReflectance = e.reflectance.maxComponent();
    return;
  }
  Rgb emission;
  double maxRadiosity = 0, maxReflectance = 0;
  AxisLobes lobes{};
  for (NodeRef child : clusters_[n.index].structure.children) {
    pullEmission(child);
    const Node& c = nodeOf(child);
    emission += c.emission * area(child);
    maxRadiosity = std::max(maxRadiosity, c.maxRadiosity);
    maxReflectance = std::max(maxReflectance, c.maxReflectance);
    addLobes(lobes, child, true);
  }
  GCluster& cluster = clusters_[n.index];
  cluster.node.emission = cluster.structure.area > 0 ? emission / cluster.structure.area : Rgb{};
  cluster.node.radiosity = {cluster.node.emission, Rgb{}, Rgb{}};
  cluster.node.maxRadiosity = maxRadiosity;
  cluster.node.maxReflectance = maxReflectance;
  cluster.emittedLobes = lobes;
}

void GalerkinRadiosity::addLobes(AxisLobes& lobes, NodeRef child, bool emitted) const {
  if (child.isCluster()) {
    const GCluster& c = clusters_[child.index];
    const AxisLobes& from = emitted ? c.emittedLobes : c.reflectedLobes;
    for (int f = 0; f < 6; ++f) lobes[f] += from[f];
    return;
  }
  const GElement& e = elements_[child.index];
  // An element's exitance on the lobes: emission, or its mean reflected radiosity.
  const Rgb exitance = emitted ? e.node.emission : e.node.radiosity[0] - e.node.emission;
  const std::array<double, 6> shares = exitanceShares(e.shape.normal);
  for (int f = 0; f < 6; ++f) lobes[f] += exitance * (e.area * shares[f]);
}

void GalerkinRadiosity::solve(double convergence) {
  // The links that carry light, copied together once (the pairs also hold the refinement's
  // history), and what they read and write each iteration in dense arrays beside them: the
  // elements and clusters hold far more, and the iterations run through the links many times.
  struct SolveLink {
    NodeRef receiver, source;
    std::array<double, 9> k;
    Vec3 direction;
  };
  std::vector<SolveLink> active;
  active.reserve(size_t(linkCount_));
  for (const GLink& link : links_)
    if (link.active()) active.push_back({link.receiver, link.source, link.k, link.direction});
  std::vector<LinearRgb> reflected(elements_.size()), gathered(elements_.size());
  std::vector<AxisLobes> clusterReflected(clusters_.size()), clusterGathered(clusters_.size());
  for (int iteration = 0; iteration < options_.maxIterations; ++iteration) {
    // What arrives from emission does not change between iterations: gathered in the first.
    const bool gatherDirect = iteration == 0;
    for (size_t e = 0; e < elements_.size(); ++e) {
      const Node& node = elements_[e].node;
      reflected[e] = node.radiosity;
      reflected[e][0] = node.radiosity[0] - node.emission;
      gathered[e] = {};
    }
    for (size_t c = 0; c < clusters_.size(); ++c) {
      clusterReflected[c] = clusters_[c].reflectedLobes;
      clusterGathered[c] = {};
    }
    if (gatherDirect) {
      for (GElement& e : elements_) e.node.gatheredDirect = {};
      for (GCluster& c : clusters_) c.gatheredDirectLobes = {};
    }
    for (const SolveLink& link : active) {
      // What the source sends, per unit of the link's coefficients: an element's linear
      // functions; a cluster's lobes towards the receiver.
      LinearRgb emitted{}, sent{};
      if (link.source.isCluster()) {
        if (gatherDirect)
          emitted[0] =
              exitanceToward(clusters_[link.source.index].emittedLobes, link.direction * -1.0);
        sent[0] = exitanceToward(clusterReflected[link.source.index], link.direction * -1.0);
      } else {
        if (gatherDirect) emitted[0] = elements_[link.source.index].node.emission;
        sent = reflected[link.source.index];
      }
      const int rows = link.receiver.isCluster() ? 1 : 3;
      const int columns = link.source.isCluster() ? 1 : 3;
      LinearRgb direct{}, indirect{};
      for (int beta = 0; beta < rows; ++beta)
        for (int alpha = 0; alpha < columns; ++alpha) {
          const double k = link.k[beta * 3 + alpha];
          if (gatherDirect) direct[beta] += emitted[alpha] * k;
          indirect[beta] += sent[alpha] * k;
        }
      if (link.receiver.isCluster()) {
        if (gatherDirect)
          addArriving(clusters_[link.receiver.index].gatheredDirectLobes, direct[0],
                      link.direction);
        addArriving(clusterGathered[link.receiver.index], indirect[0], link.direction);
      } else {
        LinearRgb& to = gathered[link.receiver.index];
        for (int beta = 0; beta < 3; ++beta) to[beta] += indirect[beta];
        if (gatherDirect) {
          Node& receiver = elements_[link.receiver.index].node;
          for (int beta = 0; beta < 3; ++beta) receiver.gatheredDirect[beta] += direct[beta];
        }
      }
    }
    for (size_t e = 0; e < elements_.size(); ++e) elements_[e].node.gatheredIndirect = gathered[e];
    for (size_t c = 0; c < clusters_.size(); ++c)
      clusters_[c].gatheredIndirectLobes = clusterGathered[c];
    const double change = pushPull({NodeRef::kCluster, 0}, {}, {}, {}, {});
    ++stats_.iterations;
    // Against the largest reflected radiosity, not B: a lamp's emission can be a hundred times
    // what the walls reflect, and measured against it the indirect light stopped 1% short.
    double largestReflected = 0;
    for (const GElement& e : elements_)
      if (e.isLeaf())
        largestReflected =
            std::max(largestReflected, (e.node.radiosity[0] - e.node.emission).maxComponent());
    if (change <= convergence * std::max(largestReflected, 1e-300)) break;
  }
}

double GalerkinRadiosity::pushPull(NodeRef n, const LinearRgb& direct, const LinearRgb& indirect,
                                   const AxisLobes& directLobes, const AxisLobes& indirectLobes) {
  if (n.isCluster()) {
    GCluster& cluster = clusters_[n.index];
    AxisLobes d = directLobes, i = indirectLobes;
    for (int f = 0; f < 6; ++f) {
      d[f] += cluster.gatheredDirectLobes[f];
      i[f] += cluster.gatheredIndirectLobes[f];
    }
    double change = 0, maxRadiosity = 0;
    Rgb radiosity;
    AxisLobes reflected{};
    for (NodeRef child : cluster.structure.children) {
      if (child.isCluster()) {
        change = std::max(change, pushPull(child, {}, {}, d, i));
      } else {
        // A root element takes what arrived on the lobes as it faces.
        const Vec3& normal = elements_[child.index].shape.normal;
        change = std::max(change, pushPull(child, {irradianceOn(d, normal), Rgb{}, Rgb{}},
                                           {irradianceOn(i, normal), Rgb{}, Rgb{}}, {}, {}));
      }
      const Node& c = nodeOf(child);
      radiosity += c.radiosity[0] * area(child);
      maxRadiosity = std::max(maxRadiosity, c.maxRadiosity);
      addLobes(reflected, child, false);
    }
    GCluster& again = clusters_[n.index];
    again.node.radiosity = {again.structure.area > 0 ? radiosity / again.structure.area : Rgb{},
                            Rgb{}, Rgb{}};
    again.node.maxRadiosity = maxRadiosity;
    again.reflectedLobes = reflected;
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
    const BasisTransfer& t = elements_[c].fromParent;
    change = std::max(change, pushPull({NodeRef::kElement, c}, restrictedToChild(d, t),
                                       restrictedToChild(i, t), {}, {}));
    const GElement& child = elements_[c];
    addProjectionToParent(pulled, child.node.radiosity, t, child.area / parentArea);
    maxRadiosity = std::max(maxRadiosity, child.node.maxRadiosity);
  }
  elements_[n.index].node.radiosity = pulled;
  elements_[n.index].node.maxRadiosity = maxRadiosity;
  return change;
}

}  // namespace penumbra
