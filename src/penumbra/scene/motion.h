#pragma once
// Keyframed rigid(+scale) motion (DESIGN.md §4): each keyframe gives the whole transform at an
// integer frame; between keyframes translation and scale interpolate linearly, rotation by slerp;
// outside the keyed range the nearest keyframe holds.

#include <vector>

#include "penumbra/geometry/transform.h"

namespace penumbra {

struct TrsPose {
  Vec3 translate;
  Quaternion rotate;
  Vec3 scale{1, 1, 1};

  Transform toTransform() const { return Transform::fromTrs(translate, rotate, scale); }
};

struct Keyframe {
  int frame = 0;
  TrsPose pose;
};

class Motion {
 public:
  Motion() = default;
  // Precondition: keyframes sorted by strictly increasing frame.
  explicit Motion(std::vector<Keyframe> keyframes) : keyframes_(std::move(keyframes)) {}

  bool isEmpty() const { return keyframes_.empty(); }
  const std::vector<Keyframe>& keyframes() const { return keyframes_; }
  int lastFrame() const { return keyframes_.empty() ? 0 : keyframes_.back().frame; }
  // Precondition: !isEmpty(). Accepts fractional frames (for sub-frame extrapolation).
  TrsPose poseAt(double frame) const;

 private:
  std::vector<Keyframe> keyframes_;
};

}  // namespace penumbra
