#pragma once
// Is a point within a distance of any of a set of segments? For the EEE polylines of a receiver,
// asked at every query and at every face corner during verification: the segments are sorted by
// their lower end along the coordinate axis where they spread most, so a query looks only at
// those whose span along that axis can reach it.

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "penumbra/geometry/box.h"
#include "penumbra/geometry/segment_distance.h"
#include "penumbra/geometry/vec3.h"

namespace penumbra {

class SegmentProximity {
 public:
  SegmentProximity() = default;
  explicit SegmentProximity(std::vector<std::pair<Vec3, Vec3>> segments)
      : segments_(std::move(segments)) {
    original_.resize(segments_.size());
    for (size_t i = 0; i < original_.size(); ++i) original_[i] = i;
    if (segments_.empty()) return;
    Vec3 lo = segments_[0].first, hi = lo;
    for (const auto& [a, b] : segments_)
      for (const Vec3& p : {a, b}) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
      }
    const Vec3 spread = hi - lo;
    axis_ = spread.x >= spread.y && spread.x >= spread.z ? 0 : spread.y >= spread.z ? 1 : 2;
    std::sort(original_.begin(), original_.end(),
              [&](size_t i, size_t j) { return low(segments_[i]) < low(segments_[j]); });
    std::vector<std::pair<Vec3, Vec3>> sorted;
    for (size_t i : original_) sorted.push_back(segments_[i]);
    segments_ = std::move(sorted);
    for (const auto& s : segments_) longest_ = std::max(longest_, high(s) - low(s));
    lows_.reserve(segments_.size());
    for (const auto& s : segments_) lows_.push_back(low(s));
  }

  bool empty() const { return segments_.empty(); }
  size_t size() const { return segments_.size(); }

  bool near(const Vec3& p, double distanceBound) const {
    bool found = false;
    forEachNear(p, distanceBound, [&](size_t) {
      found = true;
      return false;
    });
    return found;
  }

  // Whether some segment's bounds come within distanceBound of the box along every axis. False
  // proves that no point of the box lies within distanceBound of any segment (the gap along one
  // axis is larger); a caller whose points may lie a rounding outside the box pads the bound.
  bool mayBeNear(const Box3& box, double distanceBound) const {
    bool found = false;
    forEachSpanning(coordinate(box.min) - distanceBound, coordinate(box.max) + distanceBound,
                    [&](size_t i) {
                      const auto& [a, b] = segments_[i];
                      const Box3 reach{componentMin(a, b) - Vec3{1, 1, 1} * distanceBound,
                                       componentMax(a, b) + Vec3{1, 1, 1} * distanceBound};
                      found = reach.overlaps(box);
                      return !found;
                    });
    return found;
  }

  // Calls visit(index) with the index, in the order given to the constructor, of each segment
  // within distanceBound of p, while visit returns true.
  template <typename Visit>
  void forEachNear(const Vec3& p, double distanceBound, Visit visit) const {
    const double x = coordinate(p);
    forEachSpanning(x - distanceBound, x + distanceBound, [&](size_t i) {
      const auto& [a, b] = segments_[i];
      return distanceToSegment(p, a, b) > distanceBound || visit(original_[i]);
    });
  }

 private:
  // Calls visit(i) for each segment (by sorted position) whose span along the axis may reach
  // [from, to] (its low end at most `to`, and at least `from` less the longest span), in order,
  // while visit returns true.
  template <typename Visit>
  void forEachSpanning(double from, double to, Visit visit) const {
    auto it = std::lower_bound(lows_.begin(), lows_.end(), from - longest_);
    for (size_t i = size_t(it - lows_.begin()); i < segments_.size() && lows_[i] <= to; ++i)
      if (!visit(i)) return;
  }

  double coordinate(const Vec3& p) const { return axis_ == 0 ? p.x : axis_ == 1 ? p.y : p.z; }
  double low(const std::pair<Vec3, Vec3>& s) const {
    return std::min(coordinate(s.first), coordinate(s.second));
  }
  double high(const std::pair<Vec3, Vec3>& s) const {
    return std::max(coordinate(s.first), coordinate(s.second));
  }

  std::vector<std::pair<Vec3, Vec3>> segments_;  // sorted by their low end
  std::vector<size_t> original_;                 // each one's index before sorting
  std::vector<double> lows_;
  int axis_ = 0;
  double longest_ = 0;
};

}  // namespace penumbra
