#pragma once
// Axis-aligned bounding boxes. A default box is empty (min > max) and absorbs the first point.

#include <algorithm>
#include <array>
#include <limits>
#include <utility>

#include "penumbra/geometry/vec3.h"

namespace penumbra {

struct Box3 {
  Vec3 min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
           std::numeric_limits<double>::infinity()};
  Vec3 max{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
           -std::numeric_limits<double>::infinity()};

  bool isEmpty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void extend(const Vec3& p) {
    min = componentMin(min, p);
    max = componentMax(max, p);
  }
  void extend(const Box3& b) {
    if (b.isEmpty()) return;
    min = componentMin(min, b.min);
    max = componentMax(max, b.max);
  }
  Vec3 center() const { return (min + max) * 0.5; }
  Vec3 diagonal() const { return max - min; }
  double diagonalLength() const { return isEmpty() ? 0 : length(diagonal()); }
  // Closed-box tests: touching counts.
  bool contains(const Vec3& p) const {
    return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z &&
           p.z <= max.z;
  }
  bool overlaps(const Box3& b) const {
    return min.x <= b.max.x && b.min.x <= max.x && min.y <= b.max.y && b.min.y <= max.y &&
           min.z <= b.max.z && b.min.z <= max.z;
  }
  // The part [enter, leave] of the segment a + t (b − a), t in [0, 1], inside the closed box
  // (slab method); enter > leave when the segment misses it.
  std::pair<double, double> segmentInterval(const Vec3& a, const Vec3& b) const {
    double enter = 0, leave = 1;
    for (int k = 0; k < 3; ++k) {
      const double origin = a[k], d = b[k] - a[k];
      if (d == 0) {
        if (origin < min[k] || origin > max[k]) return {1, 0};
        continue;
      }
      double t0 = (min[k] - origin) / d, t1 = (max[k] - origin) / d;
      if (t0 > t1) std::swap(t0, t1);
      enter = std::max(enter, t0);
      leave = std::min(leave, t1);
    }
    return {enter, leave};
  }
  // Does the closed segment ab meet the closed box (callers who need certainty under rounding
  // test an expanded box)?
  bool meetsSegment(const Vec3& a, const Vec3& b) const {
    if (isEmpty()) return false;
    // The segment's own box first, without a division: most boxes tested lie beside it.
    for (int k = 0; k < 3; ++k)
      if (std::max(a[k], b[k]) < min[k] || std::min(a[k], b[k]) > max[k]) return false;
    const auto [enter, leave] = segmentInterval(a, b);
    return enter <= leave;
  }
  Box3 expanded(double margin) const {
    Box3 r = *this;
    r.min -= Vec3{margin, margin, margin};
    r.max += Vec3{margin, margin, margin};
    return r;
  }
};

// A segment prepared to be tested against many boxes: its own box and the reciprocals of its
// direction made once, where Box3::meetsSegment divides at every box (a link's segments are
// tested against each of its occluder candidates' boxes). The same answer as meetsSegment but
// where the segment passes within rounding of a box's face.
class SegmentBoxTest {
 public:
  SegmentBoxTest(const Vec3& a, const Vec3& b) : origin_(a) {
    for (int k = 0; k < 3; ++k) {
      low_[k] = std::min(a[k], b[k]);
      high_[k] = std::max(a[k], b[k]);
      const double d = b[k] - a[k];
      parallel_[k] = d == 0;
      inverse_[k] = d == 0 ? 0 : 1 / d;
    }
  }
  bool meets(const Box3& box) const {
    if (box.isEmpty()) return false;
    for (int k = 0; k < 3; ++k)
      if (high_[k] < box.min[k] || low_[k] > box.max[k]) return false;
    // The segment's box meets the box: the slabs. An axis the segment runs across no length of
    // was decided above.
    double enter = 0, leave = 1;
    for (int k = 0; k < 3; ++k) {
      if (parallel_[k]) continue;
      double t0 = (box.min[k] - origin_[k]) * inverse_[k];
      double t1 = (box.max[k] - origin_[k]) * inverse_[k];
      if (t0 > t1) std::swap(t0, t1);
      enter = std::max(enter, t0);
      leave = std::min(leave, t1);
    }
    return enter <= leave;
  }

 private:
  Vec3 origin_, inverse_, low_, high_;
  std::array<bool, 3> parallel_{};
};

// Distance from p to the nearest point of b (0 inside).
inline double distance(const Vec3& p, const Box3& b) {
  const Vec3 nearest{std::clamp(p.x, b.min.x, b.max.x), std::clamp(p.y, b.min.y, b.max.y),
                     std::clamp(p.z, b.min.z, b.max.z)};
  return distance(p, nearest);
}

}  // namespace penumbra
