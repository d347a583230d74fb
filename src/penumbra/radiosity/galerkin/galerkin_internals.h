#pragma once
// What the Galerkin solver's steps share (not part of its API).

#include <array>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include "penumbra/radiosity/galerkin/galerkin_radiosity.h"

namespace penumbra {

struct GalerkinRadiosity::Counters {
  long long pointPairs = 0;
  long long visibilityRays = 0;
  long long unoccludedLinks = 0;
  long long reusedRays = 0;  // point pairs whose visibility a move could not change
};

// A link's estimate: its coefficients and the oracle's figures.
// What an estimate computes from a pair's two ends alone (shapes, covers, cluster boxes), before
// any visibility: the same for as long as neither end changes.
struct GalerkinRadiosity::EndTerms {
  std::array<std::array<double, 4>, 4> transfers{};  // unoccluded, per point pair
  double coveredHighest = 0;                         // the largest transfer a cover took away
  double nearSpread = 0;  // elements nearly face to face: the exact form factors' spread
  bool near = false;
  // The ends can exchange light (canExchange) but no point pair faces: what the transfer may be
  // where the cubature points do not look (0 when some pair faces).
  double blindSpread = 0;
  // A cluster end: the transfer a surface facing the other end could take, times how far the
  // directions between the ends' points stray from the one the lobes use (GalerkinOptions::
  // directionWeight).
  double wideSpread = 0;
};

struct GalerkinRadiosity::Estimate {
  EndTerms ends;
  std::array<double, 9> k{};
  double meanTransfer = 0;    // the mean point-pair transfer
  double spread = 0;          // max − min of the point-pair transfers
  double hiddenTransfer = 0;  // what the pairs found hidden would carry (weighted as the mean)
  // With a cluster end: the pairs' directions from the receiver towards the source, weighed by
  // what each carries (axis_lobes.h), which a cluster receiver's arriving light spreads over; a
  // cluster source sends from opposite(lobes).
  LobeWeights lobes{};
  std::uint16_t hiddenPairs = 0;  // bit 4i + j: point pair (i, j) found hidden
  bool everyRay = false;          // a ray per pair, without the candidate-box test first
};

// What an update may keep of a pair's visibility: the stored answers of the point pairs whose
// segments miss every moved box (their candidates and the rays they could meet are as before).
struct GalerkinRadiosity::VisibilityReuse {
  std::uint16_t hiddenPairs = 0;
  bool everyRay = false;
  const std::vector<Box3>* movedBoxes = nullptr;
  // The point pairs (bit 4i + j, as hiddenPairs) whose two points are as covered as they were:
  // where an end's cover changed, a point that was or is now covered had no ray or needs one.
  std::uint16_t sameCover = 0xFFFF;
  // The pair's end terms from its last estimate, if kept (GalerkinRadiosity::lastEnds_).
  const EndTerms* ends = nullptr;
};

// What a move changed, for the line-space update's walk.
struct GalerkinRadiosity::Move {
  // Per element, what the move changed of it: its shape (re-posed), or only which of its points
  // a polygon in contact covers (re-covered: its bounds, and so its pairs' shafts and occluder
  // candidates, are as they were). Per cluster: whether it was refitted.
  enum ElementChange : char { kUnchanged, kReposed, kRecovered };
  std::vector<char> elementChanged, clusterChanged;
  // Which points (bit i: cubature point i, as GElement::coveredPoints) of each re-covered
  // element changed cover.
  std::unordered_map<int, std::uint8_t> coverFlipped;
  std::vector<char> movedPolygon;
  std::vector<Box3> boxes;  // the moved objects' boxes before and after, grown (in that order)
  // The bounds at the last pose of what the move changed (the shafts the pairs' old candidates
  // came from): the re-posed elements', and every cluster's.
  std::unordered_map<int, Box3> elementBoundsBefore;
  std::vector<Box3> clusterBoundsBefore;
  // The moved polygons, ascending, with their bounds at the last pose; a pair's moved part
  // (GalerkinRadiosity::MovedPart) holds positions in these.
  std::vector<PolygonId> movedIds;
  std::vector<Box3> movedBoundsBefore;
  // Blocks of at most kBlockSize consecutive moved polygons of one object, with their bounds
  // before and after: a shaft that holds a block's box whole, or misses it, decides for all of
  // its polygons at once (GalerkinRadiosity::movedPart).
  static constexpr std::size_t kBlockSize = 8;
  std::vector<std::uint32_t> blockOf;  // per moved polygon
  std::vector<Box3> blockBoundsBefore, blockBoundsAfter;
  std::shared_ptr<const std::vector<std::uint32_t>> everyMoved;  // the root's moved part
  // Did what a pair's estimate reads of this end change?
  bool endChanged(NodeRef n) const {
    return n.isCluster() ? clusterChanged[n.index] != 0 : elementChanged[n.index] != kUnchanged;
  }
  // Did its bounds change (and with them the shafts of its pairs)?
  bool boundsChanged(NodeRef n) const {
    return n.isCluster() ? clusterChanged[n.index] != 0 : elementChanged[n.index] == kReposed;
  }
  // The point pairs of a pair (bit 4i + j: receiver point i, source point j, as
  // VisibilityReuse::hiddenPairs) whose two points kept their cover.
  std::uint16_t sameCover(NodeRef receiver, NodeRef source) const {
    const auto flipped = [&](NodeRef n) -> std::uint8_t {
      if (n.isCluster()) return 0;
      const auto at = coverFlipped.find(n.index);
      return at == coverFlipped.end() ? 0 : at->second;
    };
    const std::uint8_t rows = flipped(receiver), columns = flipped(source);
    std::uint16_t same = 0xFFFF;
    for (int k = 0; k < 4; ++k) {
      if ((rows >> k) & 1u) same &= std::uint16_t(~(0xFu << (4 * k)));
      if ((columns >> k) & 1u) same &= std::uint16_t(~(0x1111u << k));
    }
    return same;
  }
};

// The solve's sums between solves (galerkin_solve.cpp).
struct GalerkinRadiosity::SolveState {
  // A link whose light the sums hold, as it was when added (what taking it back subtracts).
  struct Carried {
    NodeRef receiver, source;
    std::array<double, 9> k;
    LobeWeights lobes;
    int pair = 0;
  };
  bool valid = false;
  // The carried links by source element or cluster (together: the iterations carry a source's
  // change over all its links at once), and per pair where in its source's list it is carried
  // (kNotCarried: not), so that a change takes it back without searching the list.
  static constexpr std::int32_t kNotCarried = -1;
  std::vector<std::vector<Carried>> fromElement, fromCluster;
  std::vector<std::int32_t> carriedAt;
  bool isCarried(int pair) const {
    return size_t(pair) < carriedAt.size() && carriedAt[size_t(pair)] != kNotCarried;
  }
  // Appends a pair's link to its source's list and records where.
  Carried& carry(const Carried& link) {
    std::vector<Carried>& list = fromSource(link.source);
    carriedAt[size_t(link.pair)] = std::int32_t(list.size());
    list.push_back(link);
    return list.back();
  }
  // Per element and per cluster: what each source's links last carried (reflected radiosity,
  // B − M; a cluster's lobes), and the sums of K x sent they made at their receivers.
  std::vector<LinearRgb> sent, gathered;
  std::vector<AxisLobes> clusterSent, clusterGathered;
  // The emission the direct sums were made with: if it changed, they are made again.
  std::vector<Rgb> emission;
  std::vector<AxisLobes> clusterEmitted;
  std::vector<Carried>& fromSource(NodeRef s) {
    return s.isCluster() ? fromCluster[s.index] : fromElement[s.index];
  }
};

}  // namespace penumbra
