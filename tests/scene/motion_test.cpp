#include "penumbra/scene/motion.h"

#include <gtest/gtest.h>

namespace penumbra {
namespace {

TEST(Motion, LinearTranslationAndScale) {
  const Motion motion({{0, {{0, 0, 0}, Quaternion::identity(), {1, 1, 1}}},
                       {4, {{4, 8, 0}, Quaternion::identity(), {3, 1, 1}}}});
  const TrsPose quarter = motion.poseAt(1);
  EXPECT_EQ(quarter.translate, (Vec3{1, 2, 0}));
  EXPECT_EQ(quarter.scale, (Vec3{1.5, 1, 1}));
  EXPECT_EQ(motion.poseAt(-3).translate, (Vec3{0, 0, 0}));
  EXPECT_EQ(motion.poseAt(9).translate, (Vec3{4, 8, 0}));
  EXPECT_EQ(motion.lastFrame(), 4);
}

TEST(Motion, KeyframesAreHitExactly) {
  const Motion motion({{0, {{0, 0, 0}, Quaternion::identity(), {1, 1, 1}}},
                       {1, {{0.1, 0.2, 0.3}, Quaternion::fromAxisAngle({1, 2, 3}, 0.7), {1, 1, 1}}},
                       {5, {{-1, 0, 2}, Quaternion::fromAxisAngle({0, 1, 0}, 2.0), {2, 2, 2}}}});
  for (const Keyframe& k : motion.keyframes()) {
    const TrsPose p = motion.poseAt(k.frame);
    EXPECT_EQ(p.translate, k.pose.translate);
    EXPECT_NEAR(std::abs(p.rotate.dotWith(k.pose.rotate)), 1.0, 1e-15);
  }
}

}  // namespace
}  // namespace penumbra
