// Galerkin refinement: the power oracle, splitting the larger end of a link, element subdivision.

#include <algorithm>
#include <memory>
#include <optional>
#include <sstream>
#include <type_traits>

#include "penumbra/base/input_error.h"
#include "penumbra/base/parallel_for.h"
#include "penumbra/base/stopwatch.h"
#include "penumbra/radiosity/galerkin/galerkin_internals.h"

namespace penumbra {

namespace {

InputError budgetExceeded(double tolerance, const char* what, long long limit) {
  std::ostringstream problem;
  problem << "refining to tolerance " << tolerance << " needs more than " << limit << " " << what
          << " (the solver's budget: --max-" << what
          << "); use a larger tolerance or raise the budget";
  return InputError("--tolerance", problem.str());
}

}  // namespace

// The power a link may misplace: over the receiver's area, the source's largest radiosity times
// how much the point-pair transfers differ (a linear function cannot follow more); plus, where
// some pairs are hidden and some not, the smaller of the hidden and the visible transfer
// (weighted: GalerkinOptions::hiddenWeight); where every point pair is hidden, the hidden
// transfer (GalerkinOptions::wholeHiddenWeight); plus the whole transfer at a cluster end
// (its surfaces are taken as a whole) and at an element partly covered by a polygon in contact.
double GalerkinRadiosity::oracle(NodeRef r, NodeRef s, double meanTransfer, double spread,
                                 double hiddenTransfer) const {
  return area(r) * nodeOf(s).maxRadiosity *
         oracleVariation(r, s, meanTransfer, spread, hiddenTransfer);
}

double GalerkinRadiosity::oracleVariation(NodeRef r, NodeRef s, double meanTransfer, double spread,
                                          double hiddenTransfer) const {
  double variation = spread + options_.hiddenWeight * std::min(hiddenTransfer, meanTransfer);
  if (meanTransfer == 0) variation += options_.wholeHiddenWeight * hiddenTransfer;
  if (r.isCluster() || s.isCluster()) variation += meanTransfer;
  // A partly covered end: the covered part's share goes to (or comes from) the exposed part.
  const auto partlyCovered = [&](NodeRef n) {
    return n.isElement() && elements_[n.index].cover == GElement::kPartlyCovered;
  };
  if (partlyCovered(r) || partlyCovered(s)) variation += meanTransfer;
  return variation;
}

GalerkinRadiosity::PassKey GalerkinRadiosity::passKeyOf(const GLink& link) const {
  PassKey key;
  key.state = link.state;
  if (link.state != GLink::kActive && link.state != GLink::kPassive) return key;
  key.receiverArea = area(link.receiver);
  key.variation = oracleVariation(link.receiver, link.source, link.meanTransfer, link.spread,
                                  link.hiddenTransfer);
  key.source = link.source;
  return key;
}

const GalerkinRadiosity::PassKey& GalerkinRadiosity::passKey(int pair) {
  if (passKeyStale_[size_t(pair)]) {
    passKeys_[size_t(pair)] = passKeyOf(links_[size_t(pair)]);
    passKeyStale_[size_t(pair)] = 0;
  }
  return passKeys_[size_t(pair)];
}

double GalerkinRadiosity::oracleOf(NodeRef r, NodeRef s, const Estimate& e) const {
  return oracle(r, s, float(e.meanTransfer), float(e.spread), float(e.hiddenTransfer));
}

bool GalerkinRadiosity::canSplit(NodeRef n) const {
  return n.isCluster() || elements_[n.index].area > minArea_;
}

std::optional<NodeRef> GalerkinRadiosity::endToSplit(NodeRef r, NodeRef s) const {
  const NodeRef larger = size(r) >= size(s) ? r : s, smaller = larger == r ? s : r;
  if (canSplit(larger)) return larger;
  if (canSplit(smaller)) return smaller;
  return std::nullopt;
}

void GalerkinRadiosity::queueChildren(NodeRef r, NodeRef s, NodeRef end,
                                      const Candidates& candidates, int parent,
                                      std::vector<RefineTask>& wave) {
  for (NodeRef child : children(end))
    wave.push_back(end == r ? RefineTask{child, s, candidates, parent}
                            : RefineTask{r, child, candidates, parent});
}

GalerkinRadiosity::Candidates GalerkinRadiosity::shared(std::vector<PolygonId> own,
                                                        const Candidates& inherited) {
  // A subset of the same size is the same list; and most deep pairs' lists are empty.
  static const Candidates kNone = std::make_shared<const std::vector<PolygonId>>();
  if (own.size() == inherited->size()) return inherited;
  if (own.empty()) return kNone;
  // Copied to its size: grown one by one, the vector holds up to twice what it uses.
  return std::make_shared<const std::vector<PolygonId>>(own.begin(), own.end());
}

void GalerkinRadiosity::keepCandidates(GLink& link, const Candidates& own) {
  link.candidates = own;
  link.candidateCount = std::uint32_t(own->size());
  touchShaft(int(&link - links_.data()));
}

void GalerkinRadiosity::touchShaft(int pair) {
  links_[size_t(pair)].shaftUsed = serial_;
  if (managed()) shaftHolders_.push_back(pair);
}

const GalerkinRadiosity::Candidates& GalerkinRadiosity::candidatesFor(int pair) {
  GLink& link = links_[pair];
  if (!link.candidates) {
    const Candidates& inherited = candidatesFor(link.parent);
    GLink& made = links_[pair];
    ++listsMade_;
    made.candidates =
        made.state == GLink::kSelf
            ? inherited
            : shared(shaftCandidates(made.receiver, made.source, *inherited), inherited);
  }
  touchShaft(pair);
  return links_[pair].candidates;
}

void GalerkinRadiosity::storeEstimate(GLink& link, const Estimate& e) {
  link.k = e.k;
  link.lobes = e.lobes;
  link.meanTransfer = float(e.meanTransfer);
  link.spread = float(e.spread);
  link.hiddenTransfer = float(e.hiddenTransfer);
  link.hiddenPairs = e.hiddenPairs;
  link.everyRay = e.everyRay;
}

int GalerkinRadiosity::appendPair(const RefineTask& task, GLink::State state,
                                  const Estimate* estimate) {
  if (state == GLink::kActive || state == GLink::kPassive) {
    if (linkCount_ >= options_.maxLinks)
      throw budgetExceeded(options_.tolerance, "links", options_.maxLinks);
    ++linkCount_;
  }
  GLink link;
  link.receiver = task.receiver;
  link.source = task.source;
  if (estimate) storeEstimate(link, *estimate);
  link.state = state;
  link.parent = task.parent;
  const int index = int(links_.size());
  // A task's siblings are queued together and each task appends one pair, in order: children
  // stay contiguous.
  if (task.parent >= 0) {
    GLink& parent = links_[task.parent];
    if (parent.firstChild < 0) parent.firstChild = index;
    ++parent.childCount;
  }
  links_.push_back(std::move(link));
  beforeChange(index);  // new: the next solve carries it
  return index;
}

long long GalerkinRadiosity::dropChildren(int pair) {
  long long dropped = 0;
  GLink& link = links_[pair];
  const int first = link.firstChild, count = link.childCount;
  link.firstChild = -1;
  link.childCount = 0;
  for (int c = first; c < first + count; ++c) {
    dropped += 1 + dropChildren(c);
    beforeChange(c);
    GLink& child = links_[c];
    if (child.state == GLink::kActive || child.state == GLink::kPassive) --linkCount_;
    child.state = GLink::kDropped;
    child.candidates.reset();
    ++droppedPairs_;
  }
  return dropped;
}

std::vector<NodeRef> GalerkinRadiosity::children(NodeRef n) {
  if (n.isCluster()) return clusters_[n.index].structure.children;
  const int first = splitElement(n.index);
  return {{NodeRef::kElement, first},
          {NodeRef::kElement, first + 1},
          {NodeRef::kElement, first + 2},
          {NodeRef::kElement, first + 3}};
}

int GalerkinRadiosity::splitElement(int index) {
  if (elements_[index].firstChild >= 0) return elements_[index].firstChild;
  if ((long long)elements_.size() + 4 > options_.maxElements)
    throw budgetExceeded(options_.tolerance, "elements", options_.maxElements);
  const GElement parent = elements_[index];
  const int first = int(elements_.size());
  const auto childVertices = parent.shape.childVertices();
  for (const auto& vertices : childVertices) {
    GElement child;
    shapeChild(parent, vertices, child);
    child.polygon = parent.polygon;
    child.parent = index;
    child.reflectance = parent.reflectance;
    child.node.emission = parent.node.emission;
    child.node.maxReflectance = parent.node.maxReflectance;
    child.node.maxRadiosity = parent.node.maxRadiosity;
    // The parent's radiosity restricted to the child, until the next solve: the oracle of a
    // later pass reads it.
    child.node.radiosity = restrictedToChild(parent.node.radiosity, child.fromParent);
    child.cover = freshCover(child);
    child.coveredPoints = coveredPointsOf(child);
    elements_.push_back(child);
  }
  elements_[index].firstChild = first;
  return first;
}

void GalerkinRadiosity::shapeChild(const GElement& parent, const std::array<Vec3, 4>& vertices,
                                   GElement& child) {
  child.shape.vertices = vertices;
  child.shape.vertexCount = parent.shape.vertexCount;
  child.shape.normal = parent.shape.normal;
  prepare(child);
  child.fromParent = basisTransfer(parent.basis, child.basis, child.shape);
  child.area = elementArea(vertices, parent.shape.vertexCount);
}

void GalerkinRadiosity::compactPairs() {
  // Breadth first from the root pair, each pair's children placed together: the order keeps
  // children contiguous and parents before their children, as refinement makes them.
  std::vector<int> order{0}, newIndex(links_.size(), -1);
  newIndex[0] = 0;
  for (size_t at = 0; at < order.size(); ++at) {
    const GLink& link = links_[order[at]];
    for (int c = link.firstChild; c < link.firstChild + link.childCount; ++c) {
      newIndex[c] = int(order.size());
      order.push_back(c);
    }
  }
  // With room for an eighth more: the next update appends pairs, and a vector sized to fit
  // moves every record on its first append (the first update after a build spent 7 of its 52
  // ms in that move and the elements', on the furnished room).
  std::vector<GLink> compact;
  compact.reserve(order.size() + order.size() / 8);
  for (int old : order) {
    GLink link = std::move(links_[old]);
    if (link.parent >= 0) link.parent = newIndex[link.parent];
    if (link.firstChild >= 0) link.firstChild = newIndex[link.firstChild];
    compact.push_back(std::move(link));
  }
  links_ = std::move(compact);
  droppedPairs_ = 0;
  // What names pairs by their places, renamed: the solve's sums, and what the last update's
  // walk kept for the next.
  renumberSolveStatePairs(newIndex, links_.size());
  if (!passKeys_.empty()) {
    std::vector<PassKey> keys(links_.size());
    std::vector<char> stale(links_.size(), 1);  // pairs appended since their last pass
    for (size_t i = 0; i < passKeys_.size(); ++i)
      if (newIndex[i] >= 0) {
        keys[size_t(newIndex[i])] = passKeys_[i];
        stale[size_t(newIndex[i])] = passKeyStale_[i];
      }
    passKeys_ = std::move(keys);
    passKeyStale_ = std::move(stale);
  }
  const auto renamed = [&](auto& byPair) {
    std::remove_reference_t<decltype(byPair)> kept;
    for (auto& [pair, value] : byPair)
      if (newIndex[size_t(pair)] >= 0) kept.emplace(newIndex[size_t(pair)], std::move(value));
    byPair = std::move(kept);
  };
  renamed(lastMovedAfter_);
  renamed(lastEndsOf_);
  shaftHolders_.clear();  // renumbered: the pairs holding lists named again
  if (managed())
    for (size_t i = 1; i < links_.size(); ++i)
      if (links_[i].candidates) shaftHolders_.push_back(int(i));
}

long long GalerkinRadiosity::compactElements() {
  // Which elements a pair names; an element's split is kept while its subtree holds one.
  std::vector<char> needed(elements_.size(), 0);
  for (const GLink& link : links_) {
    if (link.state == GLink::kDropped) continue;
    if (link.receiver.isElement()) needed[link.receiver.index] = 1;
    if (link.source.isElement()) needed[link.source.index] = 1;
  }
  // Children come after their parent (a split appends them): from the back, each element learns
  // whether its subtree is needed before its parent asks.
  for (int e = int(elements_.size()) - 1; e >= 0; --e) {
    GElement& element = elements_[e];
    if (element.firstChild < 0) continue;
    bool childNeeded = false;
    for (int c = 0; c < 4; ++c) childNeeded = childNeeded || needed[element.firstChild + c];
    if (childNeeded)
      needed[e] = 1;
    else
      element.firstChild = -1;  // merged back: a leaf again, as a fresh build would leave it
  }
  // The elements still reachable from the roots, renumbered in their order (parents before
  // children, each split's four children together).
  std::vector<char> reachable(elements_.size(), 0);
  for (const std::vector<int>& roots : polygonRoots_)
    for (int root : roots) reachable[root] = 1;
  for (size_t e = 0; e < elements_.size(); ++e)
    if (reachable[e] && elements_[e].firstChild >= 0)
      for (int c = 0; c < 4; ++c) reachable[elements_[e].firstChild + c] = 1;
  std::vector<int> newIndex(elements_.size(), -1);
  int count = 0;
  for (size_t e = 0; e < elements_.size(); ++e)
    if (reachable[e]) newIndex[e] = count++;
  const long long released = (long long)elements_.size() - count;
  if (released == 0) return 0;
  renumberSolveStateElements(newIndex, size_t(count));
  std::vector<GElement> compact;  // with room for the next splits (see compactPairs)
  compact.reserve(size_t(count) + size_t(count) / 8);
  for (size_t e = 0; e < elements_.size(); ++e) {
    if (!reachable[e]) continue;
    GElement element = std::move(elements_[e]);
    if (element.parent >= 0) element.parent = newIndex[element.parent];
    if (element.firstChild >= 0) element.firstChild = newIndex[element.firstChild];
    compact.push_back(std::move(element));
  }
  elements_ = std::move(compact);
  const auto renumber = [&](NodeRef& n) {
    if (n.isElement()) n.index = newIndex[n.index];
  };
  for (GLink& link : links_) {
    renumber(link.receiver);
    renumber(link.source);
  }
  for (PassKey& key : passKeys_) renumber(key.source);
  for (std::vector<int>& roots : polygonRoots_)
    for (int& root : roots) root = newIndex[root];
  for (int& root : rootOrder_) root = newIndex[root];
  for (GCluster& cluster : clusters_)
    for (NodeRef& child : cluster.structure.children) renumber(child);
  return released;
}

// Refinement runs in waves, breadth first: each wave's node pairs are estimated in parallel
// (reading the hierarchy only), then decided in order on one thread, which splits elements,
// appends links and queues the next wave. So the hierarchy and the links' order are the same for
// any number of threads.
void GalerkinRadiosity::refine(std::vector<RefineTask> wave, Counters& counters) {
  struct Outcome {
    bool exchanges = false;
    Candidates own;
    Estimate estimate;
    Counters counters;
  };
  while (!wave.empty()) {
    std::vector<Outcome> outcomes(wave.size());
    parallelFor((long long)wave.size(), options_.threads, [&](long long i) {
      const RefineTask& task = wave[i];
      Outcome& out = outcomes[i];
      out.exchanges = canExchange(task.receiver, task.source);
      if (!out.exchanges || task.receiver == task.source) return;
      out.own =
          shared(shaftCandidates(task.receiver, task.source, *task.candidates), task.candidates);
      out.estimate =
          estimate(task.receiver, task.source, CandidateView::of(*out.own), out.counters);
    });
    std::vector<RefineTask> next;
    for (size_t i = 0; i < wave.size(); ++i) {
      const RefineTask& task = wave[i];
      const NodeRef r = task.receiver, s = task.source;
      Outcome& out = outcomes[i];
      counters.pointPairs += out.counters.pointPairs;
      counters.visibilityRays += out.counters.visibilityRays;
      counters.unoccludedLinks += out.counters.unoccludedLinks;
      if (!out.exchanges) {
        appendPair(task, GLink::kNone, nullptr);
        continue;
      }
      if (r == s) {  // a cluster with itself: every pair of its children
        const int pair = appendPair(task, GLink::kSelf, nullptr);
        keepCandidates(links_[pair], task.candidates);
        const std::vector<NodeRef> parts = children(r);
        for (NodeRef a : parts)
          for (NodeRef b : parts) next.push_back({a, b, task.candidates, pair});
        continue;
      }
      const Estimate& e = out.estimate;
      if (oracleOf(r, s, e) > threshold_)
        if (const std::optional<NodeRef> end = endToSplit(r, s); end && !deferSplit()) {
          const int pair = appendPair(task, GLink::kPassive, &e);
          links_[pair].splitReceiver = *end == r;
          keepCandidates(links_[pair], out.own);
          queueChildren(r, s, *end, out.own, pair, next);
          continue;
        }
      keepCandidates(links_[appendPair(task, GLink::kActive, &e)], out.own);
    }
    wave = std::move(next);
  }
}

GalerkinRadiosity::Settling GalerkinRadiosity::settle(Counters& counters, bool decideAnew) {
  Settling settling;
  Stopwatch stage;
  for (; settling.rounds + 1 < options_.refinementPasses && !overBudget(); ++settling.rounds) {
    const size_t before = links_.size();
    const double share = decideAnew && settling.rounds == 0 ? 1.0 : kCleanUpShare;
    const PassOutcome pass = refinementPass(counters, threshold_ * share);
    settling.cleanedUp += pass.cleanedUp;
    settling.dropped += pass.dropped;
    settling.added += (long long)(links_.size() - before);
    settling.refineSeconds += stage.lap();
    if (!pass.split && pass.cleanedUp == 0) {
      settling.settled = true;
      break;
    }
    solve(options_.convergence, true);
    settling.solveSeconds += stage.lap();
  }
  return settling;
}

bool GalerkinRadiosity::overBudget() const {
  return frameBudgeted_ && frameClock_.seconds() > options_.frameBudgetSeconds;
}

bool GalerkinRadiosity::deferSplit() {
  if (!overBudget()) return false;
  lastUpdate_.overBudget = true;
  ++lastUpdate_.deferredSplits;
  return true;
}

bool GalerkinRadiosity::refineActiveLinks(Counters& counters) {
  return refinementPass(counters, -1).split;
}

GalerkinRadiosity::PassOutcome GalerkinRadiosity::refinementPass(Counters& counters,
                                                                 double cleanUpBelow) {
  // One scan in storage order, where a pair comes before its descendants: a cleaned-up pair's
  // subtree is dropped before the scan reaches it, and the splits are refined after the scan, so
  // the outcome is that of a clean-up scan followed by a split scan.
  // The scan reads the pairs' keys (PassKey), each made again where its pair changed since, the
  // scan's own changes included (a cleaned-up pair's dropped subtree). Pairs appended since the
  // last pass have no key yet: stale.
  PassOutcome outcome;
  std::vector<RefineTask> wave;
  const int count = int(links_.size());
  passKeys_.resize(size_t(count));
  passKeyStale_.resize(size_t(count), 1);
  for (int i = 0; i < count; ++i) {
    const PassKey& key = passKey(i);
    if (key.state == GLink::kPassive && cleanUpBelow >= 0) {
      if (oracleOf(key) > cleanUpBelow) continue;
      outcome.dropped += dropChildren(i);
      setState(links_[i], GLink::kActive);
      ++outcome.cleanedUp;
      continue;
    }
    if (key.state != GLink::kActive || !(oracleOf(key) > threshold_)) continue;
    const GLink& link = links_[size_t(i)];
    const std::optional<NodeRef> end = endToSplit(link.receiver, link.source);
    if (!end || deferSplit()) continue;
    // Its children filter what its own estimate used (made again if it was not kept).
    const NodeRef r = link.receiver, s = link.source;
    const Candidates own = candidatesFor(i);
    beforeChange(i);
    GLink& split = links_[i];
    split.state = GLink::kPassive;
    split.splitReceiver = *end == r;
    queueChildren(r, s, *end, own, i, wave);
  }
  if (wave.empty()) return outcome;
  refine(std::move(wave), counters);
  outcome.split = true;
  return outcome;
}

}  // namespace penumbra
