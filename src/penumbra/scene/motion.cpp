#include "penumbra/scene/motion.h"

#include <algorithm>

#include "penumbra/base/check.h"

namespace penumbra {

TrsPose Motion::poseAt(double frame) const {
  CHECK(!keyframes_.empty());
  if (frame <= keyframes_.front().frame) return keyframes_.front().pose;
  if (frame >= keyframes_.back().frame) return keyframes_.back().pose;
  const auto next = std::upper_bound(keyframes_.begin(), keyframes_.end(), frame,
                                     [](double f, const Keyframe& k) { return f < k.frame; });
  const Keyframe& b = *next;
  const Keyframe& a = *(next - 1);
  const double t = (frame - a.frame) / double(b.frame - a.frame);
  return {lerp(a.pose.translate, b.pose.translate, t), slerp(a.pose.rotate, b.pose.rotate, t),
          lerp(a.pose.scale, b.pose.scale, t)};
}

}  // namespace penumbra
