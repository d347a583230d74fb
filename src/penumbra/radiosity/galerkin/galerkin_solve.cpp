// Galerkin solving: Jacobi gathering over the active links and push-pull through the hierarchy.
// Push restricts a parent's linear function to each child exactly; pull projects the children's
// functions onto the parent's basis (an area-weighted sum): neither creates nor loses energy.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include "penumbra/base/check.h"
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

// What a link delivers at its receiver (K x the source's function; a cluster end has one
// coefficient: `source[0]` is a cluster source's exitance towards the receiver).
template <class SolveLink>
LinearRgb arrivingOver(const SolveLink& link, const LinearRgb& source) {
  const int rows = link.receiver.isCluster() ? 1 : 3;
  const int columns = link.source.isCluster() ? 1 : 3;
  LinearRgb arriving{};
  for (int beta = 0; beta < rows; ++beta)
    for (int alpha = 0; alpha < columns; ++alpha)
      arriving[beta] += source[alpha] * link.k[beta * 3 + alpha];
  return arriving;
}

// The sizes of the terms arrivingOver adds up (what its rounding is measured against).
template <class SolveLink>
LinearRgb magnitudeOver(const SolveLink& link, const LinearRgb& source) {
  const int rows = link.receiver.isCluster() ? 1 : 3;
  const int columns = link.source.isCluster() ? 1 : 3;
  LinearRgb magnitude{};
  for (int beta = 0; beta < rows; ++beta)
    for (int alpha = 0; alpha < columns; ++alpha) {
      const Rgb& s = source[alpha];
      magnitude[beta] +=
          Rgb{std::abs(s.r), std::abs(s.g), std::abs(s.b)} * std::abs(link.k[beta * 3 + alpha]);
    }
  return magnitude;
}

// Adds what a change of its source's function (`from`; a cluster's: of its lobes) brings over a
// carried link to the solve state's indirect sums.
template <class State, class Link>
void carryChange(State& state, const Link& link, const LinearRgb& from, const AxisLobes& lobes) {
  LinearRgb source{};
  if (link.source.isCluster())
    source[0] = exitanceToward(lobes, opposite(link.lobes));
  else
    source = from;
  const LinearRgb arriving = arrivingOver(link, source);
  if (link.receiver.isCluster()) {
    addArriving(state.clusterGathered[link.receiver.index], arriving[0], link.lobes);
  } else {
    LinearRgb& to = state.gathered[link.receiver.index];
    for (int beta = 0; beta < 3; ++beta) to[beta] += arriving[beta];
  }
}

// Adds (sign 1) or takes back (-1) the direct part a carried link brings to its receiver: from
// its source's emission as the state last saw it.
template <class State, class Link, class Elements, class Clusters>
void carryDirect(State& state, Elements& elements, Clusters& clusters, const Link& link,
                 double sign) {
  LinearRgb emitted{};
  emitted[0] = (link.source.isCluster()
                    ? exitanceToward(state.clusterEmitted[link.source.index], opposite(link.lobes))
                    : state.emission[link.source.index]) *
               sign;
  const LinearRgb direct = arrivingOver(link, emitted);
  if (link.receiver.isCluster()) {
    addArriving(clusters[link.receiver.index].gatheredDirectLobes, direct[0], link.lobes);
  } else {
    LinearRgb& d = elements[link.receiver.index].node.gatheredDirect;
    for (int beta = 0; beta < 3; ++beta) d[beta] += direct[beta];
  }
}

// Adds (sign 1) or takes back (-1) all a carried link brings to its receiver's sums: the direct
// part, and the indirect from what its source last sent.
template <class State, class Link, class Elements, class Clusters>
void carryLink(State& state, Elements& elements, Clusters& clusters, const Link& link,
               double sign) {
  carryDirect(state, elements, clusters, link, sign);
  if (link.source.isCluster()) {
    AxisLobes lobes = state.clusterSent[link.source.index];
    for (Rgb& lobe : lobes) lobe = lobe * sign;
    carryChange(state, link, {}, lobes);
  } else {
    LinearRgb from = state.sent[link.source.index];
    for (Rgb& c : from) c = c * sign;
    carryChange(state, link, from, {});
  }
}

// What an element's links send of its reflected radiosity (B − M). Over a partly covered element
// the links read the radiosity at its exposed cubature points only (galerkin_links.cpp), and the
// linear function through its irradiance, zero at the covered points, does not vanish there:
// with one point of four in the open it reads three quarters of its value at that point, and a
// quarter of the element's reflected light was lost (a floor with a block turned on it lost 4.7%
// of what it reflects at tolerance 3e-3). Per channel, the function is scaled so that its exposed
// points send its integral, which already holds the cover once (at most as if the exposed points'
// share sent the whole). Emission is not scaled: a covered part emits nothing.
LinearRgb sentReflection(const GalerkinRadiosity::GElement& e) {
  LinearRgb b = e.node.radiosity;
  b[0] = b[0] - e.node.emission;
  if (e.cover != GalerkinRadiosity::GElement::kPartlyCovered || e.coveredPoints == 0) return b;
  double exposedWeight = 0;
  Rgb exposed;
  for (int j = 0; j < e.cubature.count; ++j) {
    if ((e.coveredPoints >> j) & 1u) continue;
    const auto& phi = e.cubatureBasis[j];
    exposed += (b[0] + b[1] * phi[1] + b[2] * phi[2]) * e.cubature.weights[j];
    exposedWeight += e.cubature.weights[j];
  }
  if (!(exposedWeight > 0)) return b;
  const auto factor = [&](double whole, double open) {
    return whole > 0 && open > 0 ? std::min(whole / open, 1 / exposedWeight) : 1.0;
  };
  const Rgb scale{factor(b[0].r, exposed.r), factor(b[0].g, exposed.g), factor(b[0].b, exposed.b)};
  for (Rgb& c : b) c = c * scale;
  return b;
}

// What a root element takes of the irradiance that arrived on its cluster's lobes: as it faces,
// on its exposed part (what a polygon in contact covers takes nothing; addLobes gives emission
// likewise).
Rgb takenFromLobes(const AxisLobes& lobes, const GalerkinRadiosity::GElement& root) {
  return irradianceOn(lobes, root.shape.normal) * root.exposedShare;
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
  // An element's exitance on the lobes: emission, from the exposed part only, or its mean
  // reflected radiosity, whole (its irradiance, taken on the exposed share, already holds the
  // cover: sentReflection).
  const Rgb exitance = emitted ? e.node.emission : e.node.radiosity[0] - e.node.emission;
  const double sending = e.area * (emitted ? e.exposedShare : 1.0);
  const std::array<double, 6> shares = exitanceShares(e.shape.normal);
  for (int f = 0; f < 6; ++f) lobes[f] += exitance * (sending * shares[f]);
}

std::size_t GalerkinRadiosity::solveStateBytes() const {
  std::size_t bytes = changedPairs_.capacity() * sizeof(int) + pairChanged_.capacity();
  if (!solveState_) return bytes;
  const SolveState& state = *solveState_;
  bytes += sizeof(SolveState) + state.carriedAt.capacity() * sizeof(std::int32_t) +
           (state.fromElement.capacity() + state.fromCluster.capacity()) *
               sizeof(std::vector<SolveState::Carried>);
  for (const auto* lists : {&state.fromElement, &state.fromCluster})
    for (const auto& list : *lists) bytes += list.capacity() * sizeof(SolveState::Carried);
  return bytes + (state.sent.capacity() + state.gathered.capacity()) * sizeof(LinearRgb) +
         (state.clusterSent.capacity() + state.clusterGathered.capacity() +
          state.clusterEmitted.capacity()) *
             sizeof(AxisLobes) +
         state.emission.capacity() * sizeof(Rgb);
}

void GalerkinRadiosity::beforeChange(int pair) {
  if (size_t(pair) < passKeyStale_.size()) passKeyStale_[size_t(pair)] = 1;
  // Only a valid state carries changes: else the next solve gathers everything anyway.
  if (!solveState_ || !solveState_->valid) return;
  SolveState& state = *solveState_;
  if (state.isCarried(pair)) {
    // Taken back as it was added (its source is the pair's for good); the list's last link
    // takes its place.
    std::vector<SolveState::Carried>& list = state.fromSource(links_[size_t(pair)].source);
    const std::int32_t at = state.carriedAt[size_t(pair)];
    carryLink(state, elements_, clusters_, list[size_t(at)], -1);
    list[size_t(at)] = list.back();
    state.carriedAt[size_t(list[size_t(at)].pair)] = at;
    list.pop_back();
    state.carriedAt[size_t(pair)] = SolveState::kNotCarried;
  }
  if (pairChanged_.size() <= size_t(pair)) pairChanged_.resize(links_.size(), 0);
  if (pairChanged_[size_t(pair)]) return;
  pairChanged_[size_t(pair)] = 1;
  changedPairs_.push_back(pair);
}

void GalerkinRadiosity::renumberSolveStatePairs(const std::vector<int>& newIndex,
                                                size_t pairCount) {
  // The pairs changed since the last solve, renamed (a dropped one carries nothing any more).
  std::vector<int> changed;
  for (int pair : changedPairs_)
    if (newIndex[size_t(pair)] >= 0) changed.push_back(newIndex[size_t(pair)]);
  changedPairs_ = std::move(changed);
  pairChanged_.assign(pairCount, 0);
  for (int pair : changedPairs_) pairChanged_[size_t(pair)] = 1;
  if (!solveState_ || !solveState_->valid) return;
  SolveState& state = *solveState_;
  std::vector<std::int32_t> carriedAt(pairCount, SolveState::kNotCarried);
  for (size_t i = 0; i < state.carriedAt.size(); ++i)
    if (state.carriedAt[i] != SolveState::kNotCarried) {
      // A carried pair is a link, and a compaction keeps every link.
      CHECK_GE(newIndex[i], 0);
      carriedAt[size_t(newIndex[i])] = state.carriedAt[i];
    }
  state.carriedAt = std::move(carriedAt);
  for (auto* lists : {&state.fromElement, &state.fromCluster})
    for (auto& list : *lists)
      for (SolveState::Carried& link : list) link.pair = newIndex[size_t(link.pair)];
}

void GalerkinRadiosity::renumberSolveStateElements(const std::vector<int>& newIndex,
                                                   size_t elementCount) {
  if (!solveState_ || !solveState_->valid) return;
  SolveState& state = *solveState_;
  const auto renumber = [&](NodeRef& n) {
    if (n.isElement()) n.index = newIndex[size_t(n.index)];
  };
  // Elements split after the last solve have no sums yet (the next solve adds them).
  const size_t known = state.sent.size();
  std::vector<LinearRgb> sent(std::min(known, elementCount)), gathered(sent.size());
  std::vector<Rgb> emission(sent.size());
  std::vector<std::vector<SolveState::Carried>> fromElement(sent.size());
  size_t kept = 0;
  for (size_t e = 0; e < known; ++e) {
    if (newIndex[e] < 0) {
      // Merged away: no pair names it, so it carries nothing (what it gathered is residue).
      CHECK(state.fromElement[e].empty());
      continue;
    }
    // Renumbering keeps the order, so the elements known to the state come first still.
    const size_t to = size_t(newIndex[e]);
    CHECK_EQ(to, kept);
    sent[to] = state.sent[e];
    gathered[to] = state.gathered[e];
    emission[to] = state.emission[e];
    fromElement[to] = std::move(state.fromElement[e]);
    ++kept;
  }
  sent.resize(kept);
  gathered.resize(kept);
  emission.resize(kept);
  fromElement.resize(kept);
  state.sent = std::move(sent);
  state.gathered = std::move(gathered);
  state.emission = std::move(emission);
  state.fromElement = std::move(fromElement);
  for (auto* lists : {&state.fromElement, &state.fromCluster})
    for (auto& list : *lists)
      for (SolveState::Carried& link : list) {
        renumber(link.receiver);
        renumber(link.source);
      }
}

void GalerkinRadiosity::invalidateSolveState() {
  if (solveState_) solveState_->valid = false;
  changedPairs_.clear();
  pairChanged_.clear();
}

void GalerkinRadiosity::solve(double convergence, bool fromPrevious) {
  // The sums each iteration carries into are kept from one solve to the next (SolveState), in
  // dense arrays beside the elements and clusters, which hold far more.
  if (!solveState_) solveState_ = std::make_unique<SolveState>();
  SolveState& state = *solveState_;
  const size_t elementCount = elements_.size(), clusterCount = clusters_.size();
  const auto reflectedOf = [&](size_t e) { return sentReflection(elements_[e]); };
  const auto carriedOf = [&](int pair) {
    const GLink& link = links_[size_t(pair)];
    return SolveState::Carried{link.receiver, link.source, link.k, link.lobes, pair};
  };
  std::vector<LinearRgb>& sent = state.sent;
  std::vector<LinearRgb>& gathered = state.gathered;
  std::vector<AxisLobes>& clusterSent = state.clusterSent;
  std::vector<AxisLobes>& clusterGathered = state.clusterGathered;

  // From a previous solve whose sums are still valid, and with the emission they were made
  // with, only the pairs changed since are carried anew (what they carried before was taken
  // back as they changed: beforeChange). Else every sum is made again.
  bool incremental = fromPrevious && state.valid && state.clusterEmitted.size() == clusterCount &&
                     state.emission.size() <= elementCount;
  for (size_t e = 0; incremental && e < state.emission.size(); ++e)
    incremental = state.emission[e] == elements_[e].node.emission;
  for (size_t c = 0; incremental && c < clusterCount; ++c)
    incremental = state.clusterEmitted[c] == clusters_[c].emittedLobes;
  state.carriedAt.resize(links_.size(), SolveState::kNotCarried);
  if (incremental) {
    // Elements split since: nothing carried to or from them yet.
    for (size_t e = sent.size(); e < elementCount; ++e) {
      sent.push_back(reflectedOf(e));
      gathered.push_back({});
      state.emission.push_back(elements_[e].node.emission);
      state.fromElement.emplace_back();
      elements_[e].node.gatheredDirect = {};
    }
    for (int pair : changedPairs_) {
      const GLink& link = links_[size_t(pair)];
      if (!link.active()) continue;
      std::vector<SolveState::Carried>& list = state.fromSource(link.source);
      // Grown by an eighth, not doubled: the lists are kept, and an update adds a few.
      if (list.size() == list.capacity()) list.reserve(list.size() + list.size() / 8 + 2);
      carryLink(state, elements_, clusters_, state.carry(carriedOf(pair)), 1);
    }
  } else {
    state.fromElement.assign(elementCount, {});
    state.fromCluster.assign(clusterCount, {});
    std::fill(state.carriedAt.begin(), state.carriedAt.end(), SolveState::kNotCarried);
    // Each list sized to what it holds: they are kept (an update adds a few and takes a few).
    std::vector<int> elementLinks(elementCount, 0), clusterLinks(clusterCount, 0);
    for (const GLink& link : links_)
      if (link.active())
        ++(link.source.isCluster() ? clusterLinks[link.source.index]
                                   : elementLinks[link.source.index]);
    for (size_t e = 0; e < elementCount; ++e) state.fromElement[e].reserve(elementLinks[e]);
    for (size_t c = 0; c < clusterCount; ++c) state.fromCluster[c].reserve(clusterLinks[c]);
    for (size_t i = 0; i < links_.size(); ++i)
      if (links_[i].active()) state.carry(carriedOf(int(i)));
    sent.resize(elementCount);
    gathered.resize(elementCount);
    clusterSent.resize(clusterCount);
    clusterGathered.resize(clusterCount);
    state.emission.resize(elementCount);
    for (size_t e = 0; e < elementCount; ++e) state.emission[e] = elements_[e].node.emission;
    state.clusterEmitted.resize(clusterCount);
    for (size_t c = 0; c < clusterCount; ++c) state.clusterEmitted[c] = clusters_[c].emittedLobes;
    // The direct part once (emission does not change between iterations); the indirect sums
    // are made by the first iteration (gatherAll).
    for (GElement& e : elements_) e.node.gatheredDirect = {};
    for (GCluster& c : clusters_) c.gatheredDirectLobes = {};
    for (const auto* lists : {&state.fromElement, &state.fromCluster})
      for (const auto& list : *lists)
        for (const SolveState::Carried& link : list)
          carryDirect(state, elements_, clusters_, link, 1);
    state.valid = true;
  }
  for (int pair : changedPairs_) pairChanged_[size_t(pair)] = 0;
  changedPairs_.clear();

  const auto gatherAll = [&] {
    for (size_t e = 0; e < elementCount; ++e) {
      sent[e] = reflectedOf(e);
      gathered[e] = {};
    }
    for (size_t c = 0; c < clusterCount; ++c) {
      clusterSent[c] = clusters_[c].reflectedLobes;
      clusterGathered[c] = {};
    }
    for (size_t e = 0; e < elementCount; ++e)
      for (const SolveState::Carried& link : state.fromElement[e])
        carryChange(state, link, sent[e], {});
    for (size_t c = 0; c < clusterCount; ++c)
      for (const SolveState::Carried& link : state.fromCluster[c])
        carryChange(state, link, {}, clusterSent[c]);
  };
  const auto largestLeafReflected = [&] {
    double largest = 0;
    for (const GElement& e : elements_)
      if (e.isLeaf())
        largest = std::max(largest, (e.node.radiosity[0] - e.node.emission).maxComponent());
    return largest;
  };
  // From a previous solution most sources hardly change: each iteration carries only the
  // changes of the sources that changed by more than a fraction of the convergence threshold,
  // the rest kept in the sums; what is left behind is below the accuracy the solve stops at.
  double largestReflected = incremental ? largestLeafReflected() : 0;
  for (int iteration = 0; iteration < options_.maxIterations; ++iteration) {
    if (!fromPrevious || (iteration == 0 && !incremental)) {
      gatherAll();
    } else {
      const double threshold = 0.5 * convergence * largestReflected;
      for (size_t e = 0; e < elementCount; ++e) {
        const LinearRgb now = reflectedOf(e);
        LinearRgb delta;
        double largest = 0;
        for (int k = 0; k < 3; ++k) {
          delta[k] = now[k] - sent[e][k];
          largest =
              std::max({largest, std::abs(delta[k].r), std::abs(delta[k].g), std::abs(delta[k].b)});
        }
        if (largest <= threshold) continue;
        sent[e] = now;
        for (const SolveState::Carried& link : state.fromElement[e])
          carryChange(state, link, delta, {});
      }
      for (size_t c = 0; c < clusterCount; ++c) {
        AxisLobes delta;
        double largest = 0;
        for (int f = 0; f < 6; ++f) {
          delta[f] = clusters_[c].reflectedLobes[f] - clusterSent[c][f];
          largest =
              std::max(largest, std::abs(delta[f].r) + std::abs(delta[f].g) + std::abs(delta[f].b));
        }
        // Lobes carry flux (B A): compared per unit of the cluster's area.
        if (largest <= threshold * clusters_[c].structure.area) continue;
        clusterSent[c] = clusters_[c].reflectedLobes;
        for (const SolveState::Carried& link : state.fromCluster[c])
          carryChange(state, link, {}, delta);
      }
    }
    largestReflected = 0;
    const double change = pushPull({NodeRef::kCluster, 0}, {}, {}, largestReflected);
    ++stats_.iterations;
    // Against the largest reflected radiosity, not B: a lamp's emission can be a hundred times
    // what the walls reflect, and measured against it the indirect light stopped 1% short.
    if (change <= convergence * std::max(largestReflected, 1e-300)) break;
    // Frame-rate control: the next update goes on from here (it solves from this solution).
    if (overBudget()) {
      lastUpdate_.overBudget = true;
      break;
    }
  }
}

std::string GalerkinRadiosity::verifySolveState() const {
  if (!solveState_ || !solveState_->valid) return {};
  const SolveState& state = *solveState_;
  for (size_t i = 0; i < links_.size(); ++i) {
    const bool changed = i < pairChanged_.size() && pairChanged_[i] != 0;
    const bool carried = state.isCarried(int(i));
    // A changed pair was taken back as it changed; the next solve carries it.
    if (carried != (links_[i].active() && !changed))
      return "pair " + std::to_string(i) +
             (carried ? ": carried by the solve, yet not a link"
                      : ": a link the solve does not carry");
  }
  // The sums made again from the links carried, with the magnitudes they add up (what rounding
  // is measured against).
  const size_t elementCount = state.gathered.size(), clusterCount = state.clusterGathered.size();
  std::vector<LinearRgb> gathered(elementCount), direct(elementCount), scale(elementCount);
  std::vector<AxisLobes> clusterGathered(clusterCount), clusterDirect(clusterCount),
      clusterScale(clusterCount);
  long long listed = 0;
  for (size_t source = 0; source < elementCount + clusterCount; ++source) {
    const bool isCluster = source >= elementCount;
    const size_t index = isCluster ? source - elementCount : source;
    const std::vector<SolveState::Carried>& list =
        isCluster ? state.fromCluster[index] : state.fromElement[index];
    for (size_t at = 0; at < list.size(); ++at) {
      const SolveState::Carried& link = list[at];
      ++listed;
      const GLink& stored = links_[size_t(link.pair)];
      if (!state.isCarried(link.pair) || size_t(state.carriedAt[size_t(link.pair)]) != at)
        return "pair " + std::to_string(link.pair) + ": carried elsewhere in its source's list";
      if (link.source.isCluster() != isCluster || link.source.index != int(index) ||
          !(link.receiver == stored.receiver) || !(link.source == stored.source) ||
          std::memcmp(&link.k, &stored.k, sizeof link.k) != 0 || link.lobes != stored.lobes)
        return "pair " + std::to_string(link.pair) +
               ": carried by the solve as it was before a change, or under another source";
      LinearRgb reflected{}, emitted{};
      if (isCluster) {
        reflected[0] = exitanceToward(state.clusterSent[index], opposite(link.lobes));
        emitted[0] = exitanceToward(state.clusterEmitted[index], opposite(link.lobes));
      } else {
        reflected = state.sent[index];
        emitted[0] = state.emission[index];
      }
      const LinearRgb a = arrivingOver(link, reflected), d = arrivingOver(link, emitted);
      const LinearRgb magnitude = magnitudeOver(link, reflected), m = magnitudeOver(link, emitted);
      if (link.receiver.isCluster()) {
        addArriving(clusterGathered[link.receiver.index], a[0], link.lobes);
        addArriving(clusterDirect[link.receiver.index], d[0], link.lobes);
        addArriving(clusterScale[link.receiver.index], magnitude[0] + m[0], link.lobes);
      } else {
        for (int beta = 0; beta < 3; ++beta) {
          gathered[link.receiver.index][beta] += a[beta];
          direct[link.receiver.index][beta] += d[beta];
          scale[link.receiver.index][beta] += magnitude[beta] + m[beta];
        }
      }
    }
  }
  long long carriedCount = 0;
  for (std::int32_t at : state.carriedAt) carriedCount += at != SolveState::kNotCarried;
  if (listed != carriedCount) return "the solve lists a pair twice, or leaves one out";
  // Each add and take-back rounds by an ulp of the running sum, which may have held terms since
  // taken back (a receiver that lost its links keeps a residue of what they carried): allowed
  // 1e-9 of the terms it holds, and at least 1e-12 of the largest sum anywhere. A link carried
  // wrongly or not at all is off by its whole term.
  double largest = 0;
  for (const LinearRgb& s : scale)
    for (const Rgb& c : s) largest = std::max(largest, c.maxComponent());
  for (const AxisLobes& s : clusterScale)
    for (const Rgb& c : s) largest = std::max(largest, c.maxComponent());
  const auto near = [&](const Rgb& a, const Rgb& b, const Rgb& s) {
    const auto within = [&](double x, double y, double size) {
      return std::abs(x - y) <= 1e-9 * size + 1e-12 * largest;
    };
    return within(a.r, b.r, s.r) && within(a.g, b.g, s.g) && within(a.b, b.b, s.b);
  };
  for (size_t e = 0; e < elementCount; ++e)
    for (int beta = 0; beta < 3; ++beta)
      if (!near(gathered[e][beta], state.gathered[e][beta], scale[e][beta]) ||
          !near(direct[e][beta], elements_[e].node.gatheredDirect[beta], scale[e][beta]))
        return "element " + std::to_string(e) + ": the solve's sums are not its links' sums";
  for (size_t c = 0; c < clusterCount; ++c)
    for (int f = 0; f < 6; ++f)
      if (!near(clusterGathered[c][f], state.clusterGathered[c][f], clusterScale[c][f]) ||
          !near(clusterDirect[c][f], clusters_[c].gatheredDirectLobes[f], clusterScale[c][f]))
        return "cluster " + std::to_string(c) + ": the solve's sums are not its links' sums";
  return {};
}

double GalerkinRadiosity::pushPull(NodeRef n, const LinearRgb& arrived,
                                   const AxisLobes& arrivedLobes, double& largestReflected) {
  const SolveState& state = *solveState_;
  if (n.isCluster()) {
    GCluster& cluster = clusters_[n.index];
    AxisLobes a = arrivedLobes;
    for (int f = 0; f < 6; ++f)
      a[f] += cluster.gatheredDirectLobes[f] + state.clusterGathered[n.index][f];
    double change = 0, maxRadiosity = 0;
    Rgb radiosity;
    AxisLobes reflected{};
    for (NodeRef child : cluster.structure.children) {
      if (child.isCluster()) {
        change = std::max(change, pushPull(child, {}, a, largestReflected));
      } else {
        change = std::max(
            change, pushPull(child, {takenFromLobes(a, elements_[child.index]), Rgb{}, Rgb{}}, {},
                             largestReflected));
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
  LinearRgb a;
  for (int k = 0; k < 3; ++k)
    a[k] = arrived[k] + (e.node.gatheredDirect[k] + state.gathered[n.index][k]);
  if (e.isLeaf()) {
    LinearRgb b;
    for (int k = 0; k < 3; ++k) b[k] = e.reflectance * a[k];
    b[0] += e.node.emission;
    double change = 0;
    for (int k = 0; k < 3; ++k)
      change = std::max(change, (b[k] - e.node.radiosity[k]).maxComponent());
    for (int k = 0; k < 3; ++k)
      change = std::max(change, (e.node.radiosity[k] - b[k]).maxComponent());
    e.node.radiosity = b;
    e.node.maxRadiosity = upperBound(b, e.basis.reach());
    largestReflected = std::max(largestReflected, (b[0] - e.node.emission).maxComponent());
    return change;
  }
  const int first = e.firstChild;
  const double parentArea = e.area;
  double change = 0, maxRadiosity = 0;
  LinearRgb pulled{};
  for (int c = first; c < first + 4; ++c) {
    const BasisTransfer& t = elements_[c].fromParent;
    change = std::max(
        change, pushPull({NodeRef::kElement, c}, restrictedToChild(a, t), {}, largestReflected));
    const GElement& child = elements_[c];
    addProjectionToParent(pulled, child.node.radiosity, t, child.area / parentArea);
    maxRadiosity = std::max(maxRadiosity, child.node.maxRadiosity);
  }
  elements_[n.index].node.radiosity = pulled;
  elements_[n.index].node.maxRadiosity = maxRadiosity;
  return change;
}

void GalerkinRadiosity::storeIrradiance(NodeRef n, const LinearRgb& direct,
                                        const LinearRgb& indirect, const AxisLobes& directLobes,
                                        const AxisLobes& indirectLobes) {
  const SolveState& state = *solveState_;
  if (n.isCluster()) {
    const GCluster& cluster = clusters_[n.index];
    AxisLobes d = directLobes, i = indirectLobes;
    for (int f = 0; f < 6; ++f) {
      d[f] += cluster.gatheredDirectLobes[f];
      i[f] += state.clusterGathered[n.index][f];
    }
    for (NodeRef child : cluster.structure.children) {
      if (child.isCluster()) {
        storeIrradiance(child, {}, {}, d, i);
      } else {
        const GElement& root = elements_[child.index];
        storeIrradiance(child, {takenFromLobes(d, root), Rgb{}, Rgb{}},
                        {takenFromLobes(i, root), Rgb{}, Rgb{}}, {}, {});
      }
    }
    return;
  }
  GElement& e = elements_[n.index];
  for (int k = 0; k < 3; ++k) {
    e.node.irradianceDirect[k] = direct[k] + e.node.gatheredDirect[k];
    e.node.irradianceIndirect[k] = indirect[k] + state.gathered[n.index][k];
  }
  if (e.isLeaf()) return;
  const LinearRgb d = e.node.irradianceDirect, i = e.node.irradianceIndirect;
  for (int c = e.firstChild; c < e.firstChild + 4; ++c) {
    const BasisTransfer& t = elements_[c].fromParent;
    storeIrradiance({NodeRef::kElement, c}, restrictedToChild(d, t), restrictedToChild(i, t), {},
                    {});
  }
}

}  // namespace penumbra
