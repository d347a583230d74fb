// Dynamic shaft management for the line-space update (Schöffel & Pomi 1999, "Reducing memory
// requirements for interactive radiosity using movement prediction").
//
// A pair's "shaft" here is its occluder candidate list: the box-to-box shaft itself is made from
// the ends' bounds whenever it is tested, and what costs memory is the list of polygons it may
// hold. Under ShaftPolicy::kManaged:
//  - after a build only the root pair keeps its list;
//  - an update's walk makes a met pair's list from its parent's, which the walk has just made
//    (galerkin_update.cpp), and keeps it; a refinement pass that splits a link without one makes
//    it the same way (candidatesFor);
//  - after each update, every object it moved is extrapolated a few moves ahead, and the pairs
//    whose shafts its predicted boxes meet get their lists made now, so that the next update
//    finds them (the paper's CreateShaftsOnPrediction);
//  - lists no update has used for minAge updates are released once they hold more than
//    collectAbove bytes (garbage collection by age).
// A list made again equals the one released (each is its parent's filtered by the pair's shaft,
// verifyLinks checks every kept one), so the policy never changes a result, only the cost.
//
// The prediction and the collection run on a worker thread after the update returns. It reads
// the hierarchy and writes only the pairs' lists and their ages; every call that reads or changes
// pairs waits for it first (awaitShaftWork), while the queries that read the elements' solution
// (sample, irradiance, leafMesh, powers) go on beside it. A list is immutable and shared: a
// reader holding one keeps it alive whatever the collector releases, so no address a reader holds
// ever moves or dangles.

#include <algorithm>
#include <unordered_set>

#include "penumbra/base/stopwatch.h"
#include "penumbra/radiosity/galerkin/galerkin_internals.h"
#include "penumbra/scene/scene_change.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/shaft.h"

namespace penumbra {

namespace {

// What a list holds in memory: its ids, the vector and the shared block.
std::size_t listBytes(std::size_t count) {
  return count * sizeof(PolygonId) + sizeof(std::vector<PolygonId>) + 2 * sizeof(void*);
}

}  // namespace

GalerkinRadiosity::~GalerkinRadiosity() {
  awaitShaftWork();
}

void GalerkinRadiosity::awaitShaftWork() const {
  if (shaftWorker_.joinable()) shaftWorker_.join();
}

void GalerkinRadiosity::releaseShafts() {
  for (size_t i = 1; i < links_.size(); ++i) links_[i].candidates.reset();
  shaftHolders_.clear();
}

void GalerkinRadiosity::recordPoses(const SceneChange& change) {
  // Every object that has moved gets one pose per update (the same when it stood still), so
  // that the prediction's steps are updates.
  for (const ObjectMove& move : change.moves) {
    const size_t object = size_t(move.object);
    if (object >= poses_.size()) poses_.resize(object + 1);
    std::vector<Box3>& poses = poses_[object];
    if (poses.empty()) poses.push_back(move.boundsBefore);
  }
  for (size_t object = 0; object < poses_.size(); ++object) {
    std::vector<Box3>& poses = poses_[object];
    if (poses.empty()) continue;
    const auto moved =
        std::find_if(change.moves.begin(), change.moves.end(),
                     [&](const ObjectMove& m) { return size_t(m.object) == object; });
    poses.push_back(moved != change.moves.end() ? moved->boundsAfter : poses.back());
    if (poses.size() > 3) poses.erase(poses.begin());
  }
}

std::vector<Box3> GalerkinRadiosity::predictedBoxes(const SceneChange& change) const {
  // The paper's extrapolation: with the box centre's last velocity v and acceleration a (per
  // update), the centre k updates ahead is c + k v + k(k+1)/2 a, and the box there is the
  // present one scaled by s about its centre (room for turns and for the prediction's error).
  const ShaftManagement& m = options_.management;
  std::vector<Box3> predicted;
  if (!m.prediction) return predicted;
  const double margin = 4 * rays_->epsilon() + 1e-9 * scene_.extent.diagonalLength();
  for (const ObjectMove& move : change.moves) {
    const std::vector<Box3>& poses = poses_[size_t(move.object)];
    if (poses.size() < 2) continue;
    const auto centre = [](const Box3& b) { return (b.min + b.max) * 0.5; };
    const Vec3 c = centre(poses.back());
    const Vec3 v = c - centre(poses[poses.size() - 2]);
    const Vec3 a =
        poses.size() >= 3 ? v - (centre(poses[poses.size() - 2]) - centre(poses[0])) : Vec3{};
    const Vec3 half = (poses.back().max - poses.back().min) * (0.5 * m.predictionScale);
    for (int k = 1; k <= m.predictedFrames; ++k) {
      const Vec3 at = c + v * double(k) + a * (0.5 * k * (k + 1));
      predicted.push_back(Box3{at - half, at + half}.expanded(margin));
    }
  }
  return predicted;
}

void GalerkinRadiosity::startShaftWork(const SceneChange& change) {
  if (!managed()) return;
  std::vector<Box3> predicted = predictedBoxes(change);
  if (options_.management.workerThread) {
    shaftWorker_ = std::thread(
        [this, boxes = std::move(predicted)]() mutable { manageShafts(std::move(boxes)); });
    return;
  }
  manageShafts(std::move(predicted));
  // Done in the caller's time: part of the update's.
  stats_.totalSeconds = lastUpdate_.totalSeconds += lastUpdate_.shaftSeconds;
}

void GalerkinRadiosity::manageShafts(std::vector<Box3> predicted) {
  const Stopwatch clock;
  // CreateShaftsOnPrediction: from the root, into the pairs whose shafts a predicted box meets
  // (a child's shaft lies in its parent's, so below a pair that misses, all do).
  if (!predicted.empty()) {
    std::vector<int> wave{0};
    while (!wave.empty()) {
      std::vector<int> next;
      for (int i : wave) {
        GLink& link = links_[i];
        if (link.state == GLink::kNone) continue;
        if (i > 0) {
          ++lastUpdate_.predictionTests;
          const Shaft shaft(bounds(link.receiver), bounds(link.source));
          if (std::none_of(predicted.begin(), predicted.end(),
                           [&](const Box3& box) { return shaft.mayIntersect(box); }))
            continue;
          // Made (or, already there, kept from collection) when it is worth keeping.
          if (link.candidates || worthKeeping(link)) {
            if (!link.candidates) ++lastUpdate_.shaftsPredicted;
            candidatesFor(i);
          }
        }
        for (int c = link.firstChild; c < link.firstChild + link.childCount; ++c) next.push_back(c);
      }
      wave = std::move(next);
    }
  }
  // Garbage collection by age, once the lists hold more than collectAbove bytes.
  const ShaftManagement& m = options_.management;
  // What the lists hold, each counted once unless two pairs other than parent and child share
  // it (then more than once: an estimate on the safe side, without hashing every list).
  // Every list but the root's is held by a pair named in shaftHolders_ (made or used since the
  // last collection, or kept by it): only those are looked at, not every pair.
  std::vector<int> holders;
  holders.swap(shaftHolders_);
  std::sort(holders.begin(), holders.end());
  holders.erase(std::unique(holders.begin(), holders.end()), holders.end());
  std::size_t held =
      links_.empty() || !links_[0].candidates ? 0 : listBytes(links_[0].candidates->size());
  if (m.collectAbove > 0)
    for (int i : holders) {
      const GLink& link = links_[size_t(i)];
      if (i > 0 && link.candidates && link.candidates != links_[link.parent].candidates)
        held += listBytes(link.candidates->size());
    }
  const bool collect = m.collectAbove == 0 || held > m.collectAbove;
  for (int i : holders) {
    GLink& link = links_[size_t(i)];
    if (i == 0 || !link.candidates) continue;
    // A cluster's pair with itself holds the root's list: nothing to release.
    if (collect && link.state != GLink::kSelf &&
        (serial_ - link.shaftUsed >= std::uint32_t(m.minAge) || !worthKeeping(link))) {
      link.candidates.reset();
      link.feedsMovedEnd = false;
      ++lastUpdate_.shaftsCollected;
    } else {
      shaftHolders_.push_back(i);
    }
  }
  lastUpdate_.shaftSeconds = clock.seconds();
  statsCounted_ = false;  // the lists held changed
}

bool GalerkinRadiosity::worthKeeping(const GLink& link) const {
  // A cluster's pair with itself holds its parent's list, which is the root's: nothing.
  // A list a moved object's own pairs are made from is kept while that object goes on moving:
  // else each of its moves makes it again, from the nearest ancestor that kept one. Measured on
  // the furnished room's keyframe steps (bench/radiosity_update): the walk 8.4 -> 7.0 ms and the
  // update 44.4 -> 41.5 ms; on its smooth walk (bench/radiosity_shafts) the lists held go from
  // 0.27 % to 1.14 % of every pair's (0.05 -> 0.18 MiB of 33 MiB).
  return link.state == GLink::kSelf || link.candidateCount <= options_.management.keepCount ||
         (link.feedsMovedEnd && options_.management.keepMoversParents);
}

void GalerkinRadiosity::countShafts() const {
  // Held: each distinct list once (pairs share their parent's when it is all of theirs, and
  // one empty list). Every estimated pair's: its own list where it is not its parent's.
  std::unordered_set<const void*> counted;
  stats_.shafts = 0;
  stats_.shaftBytes = 0;
  for (const GLink& link : links_)
    if (link.candidates && counted.insert(link.candidates.get()).second) {
      ++stats_.shafts;
      stats_.shaftBytes += listBytes(link.candidates->size());
    }
  // A pair's list is a subset of its parent's: of the same size, it is the parent's.
  stats_.allShaftBytes = links_.empty() ? 0 : listBytes(links_[0].candidateCount);
  bool anyEmpty = false;  // the empty lists are one
  for (const GLink& link : links_)
    if ((link.state == GLink::kActive || link.state == GLink::kPassive) &&
        link.candidateCount != links_[link.parent].candidateCount) {
      anyEmpty = anyEmpty || link.candidateCount == 0;
      if (link.candidateCount > 0) stats_.allShaftBytes += listBytes(link.candidateCount);
    }
  if (anyEmpty) stats_.allShaftBytes += listBytes(0);
}

}  // namespace penumbra
