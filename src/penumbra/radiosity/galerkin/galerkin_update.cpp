// The line-space update of the Galerkin solver (Drettakis & Sillion 1997, "Interactive update of
// global illumination using a line-space hierarchy"): after a move, only the node pairs whose
// shafts the moving objects' old or new boxes may cross are estimated again; refinement there
// splits or cleans up, and the solve starts from the previous solution.
//
// Why a pair that is not met keeps an estimate equal to a fresh one: a pair's estimate reads its
// two ends (shapes, covers, cluster boxes), its occluder candidates (the polygons of its parent's
// candidates that may meet its box-to-box shaft) and the rays along its point pairs, which stay
// inside that shaft. If neither end changed and the shaft misses both boxes (grown by the ray
// caster's tolerance), no moved polygon is or was a candidate, and no ray could meet one; and if
// its parent's candidates did not change either, neither did its own. Shaft::mayIntersect is
// monotone in the box and a child's ends lie inside its parent's, so below a pair that is not
// met nothing is: the walk stops there. verifyLinks() checks it all.
//
// A met pair whose ends' bounds and inherited static candidates are as they were needs of its own
// candidates only what changed, the moved polygons among them (an end whose cover alone changed,
// a floor element under a moved chair's feet, keeps its bounds and so the pair's shaft): those are
// filtered down the walk from the root on their own (a few ids per pair), so such a pair edits its
// kept list, or, when it kept none (ShaftPolicy::kManaged), corrects its kept count, which is all
// an estimate reads of more than kMostBoxesTested candidates (galerkin_shafts.cpp). Its point
// pairs' stored answers hold where their segments miss every moved box (a ray reads only what its
// segment may meet, and whether one is cast reads the candidates, changed only in moved polygons),
// except where a point changed cover: a covered point carries nothing, so its pairs stored no
// answer, and the gap a face contact allows may exceed the moved boxes' margin.

#include <algorithm>
#include <memory>
#include <optional>

#include "penumbra/base/parallel_for.h"
#include "penumbra/base/stopwatch.h"
#include "penumbra/radiosity/face_contacts.h"
#include "penumbra/radiosity/galerkin/galerkin_internals.h"
#include "penumbra/radiosity/hierarchy_building.h"
#include "penumbra/scene/scene_change.h"
#include "penumbra/spatial/dynamic_scene.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/shaft.h"

namespace penumbra {

namespace {

// Do two candidate lists (ascending: filtered from the root's) differ in a polygon that did not
// move?
bool staticPartDiffers(const std::vector<PolygonId>& a, const std::vector<PolygonId>& b,
                       const std::vector<char>& movedPolygon) {
  size_t i = 0, j = 0;
  while (i < a.size() || j < b.size()) {
    if (j == b.size() || (i < a.size() && a[i] < b[j])) {
      if (!movedPolygon[a[i++]]) return true;
    } else if (i == a.size() || b[j] < a[i]) {
      if (!movedPolygon[b[j++]]) return true;
    } else {
      ++i, ++j;
    }
  }
  return false;
}

}  // namespace

bool GalerkinRadiosity::reposeMovedObjects(const SceneChange& change, Move& move) {
  std::vector<char>& elementChanged = move.elementChanged;
  const auto remember = [&](int index) {
    move.elementBoundsBefore.emplace(index, elements_[index].shape.bounds());
  };
  // A moved element's descendants take their shapes from it, exactly as a first split would.
  const auto reposeBelow = [&](auto& self, int index) -> void {
    const int first = elements_[index].firstChild;
    if (first < 0) return;
    const auto childVertices = elements_[index].shape.childVertices();
    for (int c = 0; c < 4; ++c) {
      remember(first + c);
      shapeChild(elements_[index], childVertices[c], elements_[first + c]);
      elementChanged[first + c] = Move::kReposed;
      ++lastUpdate_.movedElements;
      self(self, first + c);
    }
  };
  for (const ObjectMove& move : change.moves) {
    const PolygonId begin = scene_.objectFirstPolygon[move.object];
    const PolygonId end = scene_.objectFirstPolygon[move.object + 1];
    for (PolygonId p = begin; p < end; ++p) {
      const std::vector<Element> roots = rootElementsOf(scene_, scene_.polygons[p]);
      const std::vector<int>& ids = polygonRoots_[p];
      if (roots.size() != ids.size()) return false;
      for (size_t k = 0; k < roots.size(); ++k) {
        GElement& e = elements_[ids[k]];
        if (roots[k].vertexCount != e.shape.vertexCount) return false;
        remember(ids[k]);
        e.shape = roots[k];
        prepare(e);
        e.area = roots[k].area;
        elementChanged[ids[k]] = Move::kReposed;
        ++lastUpdate_.movedElements;
        reposeBelow(reposeBelow, ids[k]);
      }
    }
  }
  return true;
}

GalerkinRadiosity::ClusterExtent GalerkinRadiosity::extentOf(const ClusterNode& cluster) const {
  // As the builder computes them: over the cluster's root elements in cluster order.
  ClusterExtent extent;
  for (int i = cluster.elementBegin; i < cluster.elementEnd; ++i) {
    const GElement& e = elements_[rootOrder_[i]];
    extent.bounds.extend(e.shape.bounds());
    extent.area += e.area;
  }
  return extent;
}

void GalerkinRadiosity::refitClusters(std::vector<char>& clusterChanged) {
  for (size_t c = 0; c < clusters_.size(); ++c) {
    ClusterNode& cluster = clusters_[c].structure;
    const ClusterExtent extent = extentOf(cluster);
    clusterChanged[c] = !(extent.bounds.min == cluster.bounds.min) ||
                        !(extent.bounds.max == cluster.bounds.max) || extent.area != cluster.area;
    cluster.bounds = extent.bounds;
    cluster.area = extent.area;
  }
}

void GalerkinRadiosity::refreshEmission(NodeRef n) {
  if (n.isElement()) return;
  Rgb emission;
  AxisLobes lobes{};
  for (NodeRef child : clusters_[n.index].structure.children) {
    refreshEmission(child);
    emission += nodeOf(child).emission * area(child);
    addLobes(lobes, child, true);
  }
  GCluster& cluster = clusters_[n.index];
  cluster.node.emission = cluster.structure.area > 0 ? emission / cluster.structure.area : Rgb{};
  cluster.emittedLobes = lobes;
}

std::optional<GalerkinRadiosity::Move> GalerkinRadiosity::prepareMove(
    const SceneChange& change, const std::vector<std::pair<PolygonId, Box3>>& moved) {
  Move move;
  move.elementChanged.assign(elements_.size(), 0);
  if (!reposeMovedObjects(change, move)) return std::nullopt;
  move.movedPolygon.assign(scene_.polygons.size(), 0);
  for (const auto& [id, box] : moved) {
    move.movedPolygon[id] = 1;
    move.movedIds.push_back(id);
    move.movedBoundsBefore.push_back(box);
  }
  for (size_t k = 0, inBlock = 0; k < move.movedIds.size(); ++k, ++inBlock) {
    const PolygonId id = move.movedIds[k];
    const auto objectOf = [&](PolygonId p) {
      return std::upper_bound(scene_.objectFirstPolygon.begin(), scene_.objectFirstPolygon.end(),
                              p) -
             scene_.objectFirstPolygon.begin();
    };
    if (k == 0 || inBlock == Move::kBlockSize || objectOf(id) != objectOf(move.movedIds[k - 1])) {
      inBlock = 0;
      move.blockBoundsBefore.emplace_back();
      move.blockBoundsAfter.emplace_back();
    }
    move.blockOf.push_back(std::uint32_t(move.blockBoundsBefore.size() - 1));
    move.blockBoundsBefore.back().extend(move.movedBoundsBefore[k]);
    move.blockBoundsAfter.back().extend(polygonBounds_[id]);
  }
  std::vector<std::uint32_t> every(move.movedIds.size());
  for (size_t k = 0; k < every.size(); ++k) every[k] = std::uint32_t(k);
  move.everyMoved = std::make_shared<const std::vector<std::uint32_t>>(std::move(every));
  // The moved objects' boxes before and after, grown by what the ray caster may round.
  const double margin = 4 * rays_->epsilon() + 1e-9 * scene_.extent.diagonalLength();
  for (const ObjectMove& m : change.moves) {
    move.boxes.push_back(m.boundsBefore.expanded(margin));
    move.boxes.push_back(m.boundsAfter.expanded(margin));
  }
  std::vector<std::vector<PolygonId>> contacts = coveringPolygons(scene_);
  for (PolygonId p = 0; p < PolygonId(contacts.size()); ++p) {
    // A cover changes with the polygons in contact, or with one of them moving.
    const bool everywhere = move.movedPolygon[p] || contacts[p] != contacts_[p];
    bool recover = everywhere;
    for (PolygonId q : contacts[p]) recover = recover || move.movedPolygon[q];
    for (PolygonId q : contacts_[p]) recover = recover || move.movedPolygon[q];
    if (!recover) continue;
    contacts_[p] = std::move(contacts[p]);
    // When only a partner moved, an element its old and new boxes both miss (and the element's
    // subtree, in its bounds) keeps its cover: the other partners stayed where they were.
    const auto partnerMayCover = [&](const GElement& e) {
      const Box3 box = e.shape.bounds();
      return std::any_of(move.boxes.begin(), move.boxes.end(),
                         [&](const Box3& moved) { return moved.overlaps(box); });
    };
    const auto recoverBelow = [&](auto& self, int index) -> void {
      GElement& e = elements_[index];
      if (!everywhere && !partnerMayCover(e)) return;
      const GElement::Cover cover = freshCover(e);
      // A partly covered element's estimates read which of its points are covered, which a
      // moving partner may change while the kind of cover stays.
      const GElement::Cover before = e.cover;
      const std::uint8_t pointsBefore = e.coveredPoints;
      e.cover = cover;
      e.coveredPoints = coveredPointsOf(e);
      if (e.parent < 0) e.exposedShare = exposedShareOf(e);
      if (cover != before || e.coveredPoints != pointsBefore) {
        ++lastUpdate_.coverChanged;
        if (move.elementChanged[index] == Move::kUnchanged) {
          move.elementChanged[index] = Move::kRecovered;
          move.coverFlipped.emplace(index, std::uint8_t(pointsBefore ^ e.coveredPoints));
        }
      }
      if (e.firstChild >= 0)
        for (int c = 0; c < 4; ++c) self(self, e.firstChild + c);
    };
    for (int root : polygonRoots_[p]) recoverBelow(recoverBelow, root);
  }
  move.clusterChanged.assign(clusters_.size(), 0);
  move.clusterBoundsBefore.reserve(clusters_.size());
  for (const GCluster& cluster : clusters_)
    move.clusterBoundsBefore.push_back(cluster.structure.bounds);
  refitClusters(move.clusterChanged);
  refreshEmission({NodeRef::kCluster, 0});
  for (char c : move.clusterChanged) lastUpdate_.clustersChanged += c;
  return move;
}

GalerkinRadiosity::MovedPart GalerkinRadiosity::movedPart(const Move& move, NodeRef r, NodeRef s,
                                                          const MovedPart& parentPart,
                                                          bool before) const {
  const std::vector<std::uint32_t>& among = *parentPart;
  // As shaftCandidates filters, on the moved polygons alone (at their old bounds before).
  static const MovedPart kNone = std::make_shared<const std::vector<std::uint32_t>>();
  if (among.empty()) return kNone;
  const Shaft shaft =
      before ? Shaft(boundsBefore(move, r), boundsBefore(move, s)) : Shaft(bounds(r), bounds(s));
  const auto [ownR, ownS] = ownPolygons(r, s);
  const std::vector<Box3>& blocks = before ? move.blockBoundsBefore : move.blockBoundsAfter;
  std::vector<std::uint32_t> part;
  for (size_t at = 0; at < among.size();) {
    // The run of `among` in one block: where the shaft holds the block's box whole (or misses
    // it), it admits (rejects) each of the run's polygons, as testing each would.
    const std::uint32_t block = move.blockOf[among[at]];
    size_t end = at + 1;
    while (end < among.size() && move.blockOf[among[end]] == block) ++end;
    const bool several = end - at > 1;
    const bool all = several && shaft.containsBox(blocks[block]);
    const bool none = several && !all && !shaft.mayIntersect(blocks[block]);
    for (; at < end; ++at) {
      const std::uint32_t k = among[at];
      const PolygonId id = move.movedIds[k];
      if (none || id == ownR || id == ownS) continue;
      if (all || shaft.mayIntersect(before ? move.movedBoundsBefore[k] : polygonBounds_[id]))
        part.push_back(k);
    }
  }
  // All of them: the parent's block, shared (most pairs near the root).
  if (part.size() == among.size()) return parentPart;
  return std::make_shared<const std::vector<std::uint32_t>>(std::move(part));
}

GalerkinRadiosity::MovedPart GalerkinRadiosity::movedAmong(const Move& move,
                                                           const std::vector<PolygonId>& own,
                                                           const MovedPart& parentPart) {
  // Both ascending: a merge.
  std::vector<std::uint32_t> part;
  size_t k = 0;
  for (PolygonId id : own) {
    if (!move.movedPolygon[id]) continue;
    while (move.movedIds[k] < id) ++k;
    part.push_back(std::uint32_t(k));
  }
  // All of the parent's: its block, shared, as movedPart returns it.
  if (part.size() == parentPart->size()) return parentPart;
  return std::make_shared<const std::vector<std::uint32_t>>(std::move(part));
}

std::vector<PolygonId> GalerkinRadiosity::withMovedPolygons(
    const Move& move, const std::vector<PolygonId>& old,
    const std::vector<std::uint32_t>& movedNow) {
  std::vector<PolygonId> merged;
  merged.reserve(old.size() + movedNow.size());
  auto next = movedNow.begin();
  for (PolygonId id : old) {
    if (move.movedPolygon[id]) continue;
    for (; next != movedNow.end() && move.movedIds[*next] < id; ++next)
      merged.push_back(move.movedIds[*next]);
    merged.push_back(id);
  }
  for (; next != movedNow.end(); ++next) merged.push_back(move.movedIds[*next]);
  return merged;
}

Box3 GalerkinRadiosity::boundsBefore(const Move& move, NodeRef n) const {
  if (n.isCluster()) return move.clusterBoundsBefore[n.index];
  const auto before = move.elementBoundsBefore.find(n.index);
  return before != move.elementBoundsBefore.end() ? before->second : bounds(n);
}

std::vector<PolygonId> GalerkinRadiosity::staticCandidatesBefore(
    const Move& move, NodeRef r, NodeRef s, const std::vector<PolygonId>& among) const {
  // shaftCandidates at the last pose, without the moved polygons (whose old bounds are gone).
  return candidatesIn(Shaft(boundsBefore(move, r), boundsBefore(move, s)), r, s, among,
                      &move.movedPolygon);
}

void GalerkinRadiosity::setState(GLink& link, GLink::State state) {
  const auto counts = [](GLink::State s) {
    return s == GLink::kActive || s == GLink::kPassive ? 1 : 0;
  };
  beforeChange(int(&link - links_.data()));
  linkCount_ += counts(state) - counts(link.state);
  link.state = state;
}

void GalerkinRadiosity::walkPairs(const Move& move, Counters& counters,
                                  std::vector<RefineTask>& fresh) {
  // How a met pair gets its candidates at the new pose:
  enum class Making : std::uint8_t {
    kFilter,  // from its parent's list (an end or the inherited candidates changed, or it
              // needs its few candidates' ids and did not keep them)
    kEdit,    // its kept list, the moved polygons replaced (ends and inheritance as they were)
    kCount,   // none: as they were but for the moved polygons, and so many (or none) that the
              // estimate reads only how many (ShaftPolicy::kManaged, the list not kept)
  };
  struct Outcome {
    bool exchanges = false;
    Making making = Making::kFilter;
    bool wasEstimated = false;  // a link or a split pair before the move
    std::size_t count = 0;      // its candidates at the new pose
    Candidates own;             // they, unless kCount
    // A split pair's candidates before the move, what its children's were filtered from: its
    // kept list, or (not kept, ShaftPolicy::kManaged) their static part made again.
    Candidates before;
    MovedPart movedBefore, movedAfter;  // the moved polygons among its candidates
    Estimate estimate;
    Counters counters;
  };
  // A pair to visit; whether its parent's candidates changed (then its own may have: the
  // conservative shaft test can admit a polygon its parent's shaft rejected); the parent's
  // candidates before the move (at least their static part; none: the same as its new ones');
  // and the moved polygons among the parent's candidates before and after the move.
  struct Visit {
    int pair = 0;
    bool inheritedChanged = false;
    Candidates inheritedBefore;
    MovedPart movedBefore, movedAfter;
  };
  std::vector<Visit> wave{{0, false, links_[0].candidates, move.everyMoved, move.everyMoved}};
  const size_t movedObjects = move.boxes.size() / 2;
  const bool sameMoved = move.movedIds == lastMovedIds_;
  std::unordered_map<int, MovedPart> movedAfter;
  std::vector<EndTerms> ends;
  std::unordered_map<int, int> endsOf;
  Stopwatch walk;
  while (!wave.empty()) {
    walk.lap();
    std::vector<Visit> met;
    for (const Visit& visit : wave) {
      const GLink& link = links_[visit.pair];
      if (visit.inheritedChanged || move.endChanged(link.receiver) ||
          move.endChanged(link.source)) {
        met.push_back(visit);
        ++lastUpdate_.endMoved;
        continue;
      }
      ++lastUpdate_.shaftTests;
      // The shaft's first test is its hull, the two ends' union: most pairs a walk visits miss
      // the moved boxes there, and then the shaft's planes need not be made.
      const Box3 receiverBounds = bounds(link.receiver), sourceBounds = bounds(link.source);
      Box3 hull = receiverBounds;
      hull.extend(sourceBounds);
      bool inHull = false;
      for (size_t m = 0; m < 2 * movedObjects && !inHull; ++m)
        inHull = hull.overlaps(move.boxes[m]);
      bool atOld = false, atNew = false;
      if (inHull) {
        const Shaft shaft(receiverBounds, sourceBounds);
        for (size_t m = 0; m < movedObjects; ++m) {
          atOld = atOld || shaft.mayIntersect(move.boxes[2 * m]);
          atNew = atNew || shaft.mayIntersect(move.boxes[2 * m + 1]);
        }
      }
      lastUpdate_.shaftsAtOld += atOld;
      lastUpdate_.shaftsAtNew += atNew;
      if (atOld || atNew) met.push_back(visit);
    }
    lastUpdate_.walkSeconds += walk.lap();
    std::vector<Outcome> outcomes(met.size());
    // Its shaft, and so its static candidates, as they were (an end that was only re-covered
    // keeps its bounds).
    const auto kept = [&](size_t m) {
      const GLink& link = links_[met[m].pair];
      return !met[m].inheritedChanged && !move.boundsChanged(link.receiver) &&
             !move.boundsChanged(link.source);
    };
    // The moved parts, and how each pair's candidates will be made (cheap: a few ids each).
    parallelFor((long long)met.size(), options_.threads, [&](long long m) {
      const GLink& link = links_[met[m].pair];
      Outcome& out = outcomes[m];
      out.exchanges = canExchange(link.receiver, link.source);
      if (!out.exchanges || link.receiver == link.source) return;
      // Before the move, the moved part is needed only to count a list that was not kept.
      if (managed()) {
        const auto last = sameMoved ? lastMovedAfter_.find(met[m].pair) : lastMovedAfter_.end();
        out.movedBefore =
            last != lastMovedAfter_.end()
                ? last->second
                : movedPart(move, link.receiver, link.source, met[m].movedBefore, true);
      }
      const bool estimated = link.state == GLink::kActive || link.state == GLink::kPassive;
      out.wasEstimated = estimated;
      // Filtered from the parent's list below, which gives its moved part after the move too.
      if (!kept(m) || !estimated) return;  // kFilter
      out.movedAfter = movedPart(move, link.receiver, link.source, met[m].movedAfter, false);
      if (link.candidates) {
        out.making = Making::kEdit;
        return;
      }
      out.count = link.candidateCount - out.movedBefore->size() + out.movedAfter->size();
      if (out.count == 0 || out.count > kMostBoxesTested) out.making = Making::kCount;
    });
    // The parents' lists the filtering pairs need, made where they were not kept (on one
    // thread: a parent may have to be made from its own parent's).
    const long long madeBefore = listsMade_;
    for (size_t m = 0; m < met.size(); ++m) {
      const GLink& link = links_[met[m].pair];
      const bool filters = outcomes[m].exchanges && link.receiver != link.source &&
                           outcomes[m].making == Making::kFilter;
      // A split pair not kept whose old list is gone remakes its static part from its parent's
      // old one, which is the parent's new one when the parent was kept.
      if (filters || (outcomes[m].exchanges && !kept(m) && link.state == GLink::kPassive &&
                      !link.candidates && !met[m].inheritedBefore))
        candidatesFor(link.parent);
      if (filters && (move.boundsChanged(link.receiver) || move.boundsChanged(link.source)))
        links_[link.parent].feedsMovedEnd = true;
    }
    lastUpdate_.shaftsMade += listsMade_ - madeBefore;
    lastUpdate_.walkSeconds += walk.lap();
    parallelFor((long long)met.size(), options_.threads, [&](long long m) {
      const GLink& link = links_[met[m].pair];
      Outcome& out = outcomes[m];
      if (!out.exchanges || link.receiver == link.source) return;
      const Candidates& inherited = links_[link.parent].candidates;  // made when filtering
      switch (out.making) {
        case Making::kFilter:
          out.own = shared(shaftCandidates(link.receiver, link.source, *inherited), inherited);
          if (!out.movedAfter) out.movedAfter = movedAmong(move, *out.own, met[m].movedAfter);
          break;
        case Making::kEdit: {
          std::vector<PolygonId> edited =
              withMovedPolygons(move, *link.candidates, *out.movedAfter);
          out.own = inherited ? shared(std::move(edited), inherited)
                              : std::make_shared<const std::vector<PolygonId>>(std::move(edited));
          break;
        }
        case Making::kCount:
          break;
      }
      if (out.own) out.count = out.own->size();
      // What its children's candidates came from, to tell whether they changed (not needed
      // when kept: then only moved polygons changed in it).
      if (link.state == GLink::kPassive && !kept(m))
        out.before = link.candidates
                         ? link.candidates
                         : std::make_shared<const std::vector<PolygonId>>(staticCandidatesBefore(
                               move, link.receiver, link.source,
                               met[m].inheritedBefore ? *met[m].inheritedBefore : *inherited));
      const bool estimated = link.state == GLink::kActive || link.state == GLink::kPassive;
      // The end terms read the ends' covers; the stored answers hold for the point pairs whose
      // points kept theirs.
      const bool endsAsBefore = !move.endChanged(link.receiver) && !move.endChanged(link.source);
      const auto last = endsAsBefore ? lastEndsOf_.find(met[m].pair) : lastEndsOf_.end();
      const VisibilityReuse reuse{
          link.hiddenPairs, link.everyRay, &move.boxes, move.sameCover(link.receiver, link.source),
          last != lastEndsOf_.end() ? &lastEnds_[size_t(last->second)] : nullptr};
      out.estimate = estimate(link.receiver, link.source, CandidateView{out.count, out.own.get()},
                              out.counters, kept(m) && estimated ? &reuse : nullptr);
    });
    std::vector<Visit> next;
    for (size_t m = 0; m < met.size(); ++m) {
      const int i = met[m].pair;
      Outcome& out = outcomes[m];
      if (out.movedAfter) movedAfter[i] = out.movedAfter;
      if (out.exchanges && !(links_[i].receiver == links_[i].source)) {
        endsOf[i] = int(ends.size());
        ends.push_back(out.estimate.ends);
      }
      counters.pointPairs += out.counters.pointPairs;
      counters.visibilityRays += out.counters.visibilityRays;
      counters.unoccludedLinks += out.counters.unoccludedLinks;
      counters.reusedRays += out.counters.reusedRays;
      ++lastUpdate_.met;
      const NodeRef r = links_[i].receiver, s = links_[i].source;
      const auto visitChildren = [&](bool candidatesChanged, const Candidates& before,
                                     const MovedPart& movedBefore, const MovedPart& movedAfter) {
        for (int c = links_[i].firstChild; c < links_[i].firstChild + links_[i].childCount; ++c)
          next.push_back({c, candidatesChanged, before, movedBefore, movedAfter});
      };
      if (!out.exchanges) {
        if (links_[i].state == GLink::kPassive) lastUpdate_.dropped += dropChildren(i);
        setState(links_[i], GLink::kNone);
        links_[i].candidates.reset();
        links_[i].candidateCount = 0;
        continue;
      }
      if (r == s) {  // a cluster with itself: its children's pairs are fixed, its candidates
                     // its parent's
        if (links_[i].parent >= 0) {
          const GLink& parent = links_[links_[i].parent];
          links_[i].candidates = parent.candidates;
          links_[i].candidateCount = parent.candidateCount;
          touchShaft(i);
        }
        visitChildren(met[m].inheritedChanged, met[m].inheritedBefore, met[m].movedBefore,
                      met[m].movedAfter);
        continue;
      }
      ++lastUpdate_.reestimated;
      if (kept(m) && (move.endChanged(r) || move.endChanged(s))) ++lastUpdate_.coverOnly;
      switch (out.making) {
        case Making::kFilter:
          // Made again under any policy where an end or the inherited list changed; else
          // only because it was not kept.
          ++(kept(m) && out.wasEstimated ? lastUpdate_.shaftsMade : lastUpdate_.shaftsRemade);
          break;
        case Making::kEdit:
          ++lastUpdate_.shaftsThere;
          break;
        case Making::kCount:
          ++lastUpdate_.shaftsCounted;
          break;
      }
      const Estimate& e = out.estimate;
      std::optional<NodeRef> end;
      if (oracleOf(r, s, e) > threshold_) end = endToSplit(r, s);
      beforeChange(i);
      GLink& link = links_[i];
      storeEstimate(link, e);
      if (out.own) {
        // The same list as before stays the same block: its children not met share it still.
        if (link.candidates && out.own != link.candidates && *out.own == *link.candidates)
          out.own = link.candidates;
        keepCandidates(link, out.own);
      } else {
        link.candidateCount = std::uint32_t(out.count);
      }
      const bool splitAlike =
          end && link.state == GLink::kPassive && link.splitReceiver == (*end == r);
      if (end && !splitAlike && deferSplit()) end.reset();  // a link until a later update
      if (splitAlike) {
        // Still split the same way: walk on. Its children's candidates can change beyond the
        // moved polygons (which their own shafts filter) only if its own gained or lost another;
        // with its ends and inherited candidates as they were, only moved polygons changed.
        if (out.before)
          visitChildren(staticPartDiffers(*out.before, *out.own, move.movedPolygon), out.before,
                        out.movedBefore, out.movedAfter);
        else
          visitChildren(false, out.own, out.movedBefore, out.movedAfter);
      } else if (end) {  // split anew: a subtree for refinement below
        lastUpdate_.dropped += dropChildren(i);
        setState(links_[i], GLink::kPassive);
        links_[i].splitReceiver = *end == r;
        const long long made = listsMade_;
        const Candidates own = candidatesFor(i);
        lastUpdate_.shaftsMade += listsMade_ - made;
        queueChildren(r, s, *end, own, i, fresh);
        ++lastUpdate_.refined;
      } else {
        if (link.state == GLink::kPassive) {
          lastUpdate_.dropped += dropChildren(i);
          ++lastUpdate_.cleanedUp;
        }
        setState(links_[i], GLink::kActive);
      }
    }
    wave = std::move(next);
  }
  lastMovedAfter_ = std::move(movedAfter);
  lastMovedIds_ = move.movedIds;
  lastEnds_ = std::move(ends);
  lastEndsOf_ = std::move(endsOf);
}

void GalerkinRadiosity::recordPasses(const Settling& settling, int passesBefore) {
  lastUpdate_.laterCleanUps = settling.cleanedUp;
  lastUpdate_.dropped += settling.dropped;
  lastUpdate_.refineSeconds += settling.refineSeconds;
  lastUpdate_.solveSeconds += settling.solveSeconds;
  stats_.passes = passesBefore + settling.passes();
  stats_.settled = settling.settled;
  if (!settling.settled && overBudget()) lastUpdate_.overBudget = true;
  frameBudgeted_ = false;
}

void GalerkinRadiosity::compactIfWorthIt() {
  // Dropped pairs stay in storage until they are a quarter of it: then it is compacted, so a
  // long walk of moves does not grow it, and the splits no pair needs any more are merged back.
  if (droppedPairs_ * 4 <= (long long)links_.size()) return;
  compactPairs();
  lastUpdate_.mergedElements = compactElements();
  lastUpdate_.compacted = true;
}

void GalerkinRadiosity::update(const DynamicScene& scene, const SceneChange& change) {
  const Stopwatch total;
  awaitShaftWork();  // the last update's shaft work, if still running
  Stopwatch stage;
  lastUpdate_ = {};
  lastUpdate_.shaftWaitSeconds = stage.lap();
  frameClock_ = total;
  ++serial_;
  recordPoses(change);
  const auto rebuild = [&](const char* reason) {
    frameBudgeted_ = false;
    build(scene);
    lastUpdate_.rebuilt = true;
    lastUpdate_.rebuildReason = reason;
    lastUpdate_.totalSeconds = total.seconds();
    startShaftWork(change);
  };
  if (elements_.empty()) return rebuild("nothing was built");
  if (change.extentGrows) return rebuild("the scene's extent grew");
  // The moved polygons, ascending, with their bounds at the last pose (the pairs' old candidates
  // were filtered by them), before takeScene replaces them.
  std::vector<std::pair<PolygonId, Box3>> moved;
  for (const ObjectMove& m : change.moves)
    for (PolygonId p = scene_.objectFirstPolygon[m.object];
         p < scene_.objectFirstPolygon[m.object + 1]; ++p)
      moved.emplace_back(p, polygonBounds_[p]);
  const auto byId = [](const auto& a, const auto& b) { return a.first < b.first; };
  std::sort(moved.begin(), moved.end(), byId);
  moved.erase(std::unique(moved.begin(), moved.end(),
                          [](const auto& a, const auto& b) { return a.first == b.first; }),
              moved.end());
  takeScene(scene);
  stats_.refineSeconds = stats_.solveSeconds = 0;
  stats_.iterations = 0;
  stats_.pointPairs = stats_.visibilityRays = stats_.unoccludedLinks = 0;
  if (change.moves.empty()) {
    // Nothing moved: what an earlier update's frame budget left undone (splits, passes, the
    // solve's iterations) goes on here, under the budget, until the solution is at rest again.
    // One pass always runs, so that each such step makes progress whatever the budget.
    if (!stats_.settled) {
      Counters counters;
      const size_t count = links_.size();
      refineActiveLinks(counters);
      lastUpdate_.refineSeconds = stage.lap();
      frameBudgeted_ = options_.frameBudgetSeconds > 0;
      solve(options_.convergence, true);
      lastUpdate_.solveSeconds = stage.lap();
      recordPasses(settle(counters), 1);
      lastUpdate_.laterSplits = (long long)(links_.size() - count);
      storeIrradiance();
      compactIfWorthIt();
      stats_.pointPairs = counters.pointPairs;
      stats_.visibilityRays = counters.visibilityRays;
      statsCounted_ = false;
    }
    stats_.totalSeconds = lastUpdate_.totalSeconds = total.seconds();
    startShaftWork(change);
    return;
  }

  frameBudgeted_ = options_.frameBudgetSeconds > 0;
  // 1. The moved objects' elements, the covers contacts give, the cluster boxes.
  const std::optional<Move> move = prepareMove(change, moved);
  if (!move) return rebuild("a moved polygon's root elements changed (its triangulation)");
  lastUpdate_.reposeSeconds = stage.lap();

  // 2. The walk from the root pair, wave by wave: the met pairs' estimates in parallel, then
  // decided in order on one thread (so the result does not depend on the threads).
  Counters counters;
  std::vector<RefineTask> fresh;
  walkPairs(*move, counters, fresh);
  lastUpdate_.traverseSeconds = stage.lap();

  // 3. New subtrees below new splits; the pass a build makes after its first solve (the oracle
  // with the radiosities the last solve left), here before the solve, as the light has moved
  // little since; a solve from the previous solution; then passes and solves until a pass
  // changes nothing, as a build ends. A moved light changes the radiosities everywhere, not only
  // near the move: there the first pass waits for the solve.
  const size_t before = links_.size();
  if (!fresh.empty()) refine(std::move(fresh), counters);
  lastUpdate_.created = (long long)(links_.size() - before);
  const size_t count = links_.size();
  // After an update that came to rest (its last pass split nothing on these radiosities), this
  // pass finds nothing to split: a pair the walk did not meet has its ends, its estimate and its
  // source's radiosity as that pass saw them, and the walk and refine() decided every pair they
  // estimated by the same oracle on the same rounded terms (oracleOf) — unless the frame budget
  // deferred a split. Then it is left out.
  const bool restedBefore = stats_.settled && lastUpdate_.deferredSplits == 0;
  if (options_.refinementPasses > 1 && !change.movesLight() && !restedBefore)
    refineActiveLinks(counters);
  lastUpdate_.laterSplits = (long long)(links_.size() - count);
  lastUpdate_.refineSeconds = stage.lap();
  solve(options_.convergence, true);
  lastUpdate_.solveSeconds = stage.lap();
  const Settling settling = settle(counters, change.movesLight());
  lastUpdate_.laterSplits += settling.added;
  recordPasses(settling, 0);
  storeIrradiance();
  compactIfWorthIt();
  stats_.pointPairs = counters.pointPairs;
  stats_.visibilityRays = counters.visibilityRays;
  stats_.unoccludedLinks = counters.unoccludedLinks;
  lastUpdate_.reusedVisibility = counters.reusedRays;
  stats_.refineSeconds = lastUpdate_.traverseSeconds + lastUpdate_.refineSeconds;
  stats_.solveSeconds = lastUpdate_.solveSeconds;
  statsCounted_ = false;
  stats_.totalSeconds = lastUpdate_.totalSeconds = total.seconds();
  startShaftWork(change);
}

}  // namespace penumbra
