// SegmentProximity against brute force: near() against the distance to every segment, and
// mayBeNear(box) as a proof of absence: where it says no, no point of the box (its corners, its
// centre, random points and the points of the box nearest to each segment's ends) lies within the
// bound of any segment; where some such point does, it says yes.

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "penumbra/dm/segment_proximity.h"

namespace penumbra {
namespace {

// The test's own distance (not geometry/segment_distance.h, which SegmentProximity uses).
double referenceDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = dot(ab, ab);
  const double t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return distance(p, a + ab * t);
}

TEST(SegmentProximity, NearAndMayBeNearAgreeWithBruteForce) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(0, 1);
  const auto point = [&] { return Vec3{unit(random), unit(random) * 0.2, unit(random)}; };
  int boxesSaidNo = 0, boxesWithANearPoint = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<std::pair<Vec3, Vec3>> segments;
    const int count = 1 + int(unit(random) * 30);
    for (int k = 0; k < count; ++k) {
      const Vec3 a = point();
      // Short and long ones, and a point (both ends equal).
      const double length = k % 7 == 0 ? 0 : unit(random) * (k % 2 ? 0.05 : 0.6);
      segments.push_back({a, a + normalize(point() - Vec3{0.5, 0.1, 0.5}) * length});
    }
    const SegmentProximity proximity(segments);
    const double bound = trial % 3 == 0 ? 1e-6 : 0.01 + 0.05 * unit(random);
    for (int q = 0; q < 20; ++q) {
      const Vec3 p = point();
      bool near = false;
      for (const auto& [a, b] : segments) near = near || referenceDistance(p, a, b) <= bound;
      EXPECT_EQ(proximity.near(p, bound), near);
    }
    for (int q = 0; q < 20; ++q) {
      Box3 box;
      box.extend(point());
      box.extend(box.min + Vec3{unit(random), unit(random), unit(random)} * 0.1);
      std::vector<Vec3> probes;
      for (int corner = 0; corner < 8; ++corner)
        probes.push_back({corner & 1 ? box.max.x : box.min.x, corner & 2 ? box.max.y : box.min.y,
                          corner & 4 ? box.max.z : box.min.z});
      probes.push_back(box.center());
      for (int k = 0; k < 20; ++k) {
        const Vec3 d = box.max - box.min;
        probes.push_back(box.min +
                         Vec3{d.x * unit(random), d.y * unit(random), d.z * unit(random)});
      }
      for (const auto& [a, b] : segments)
        for (const Vec3& end : {a, b, (a + b) * 0.5})
          probes.push_back(componentMin(componentMax(end, box.min), box.max));
      bool someNear = false;
      for (const Vec3& p : probes)
        for (const auto& [a, b] : segments)
          someNear = someNear || referenceDistance(p, a, b) <= bound;
      const bool mayBe = proximity.mayBeNear(box, bound);
      if (someNear) {
        EXPECT_TRUE(mayBe) << "trial " << trial;
        ++boxesWithANearPoint;
      }
      boxesSaidNo += mayBe ? 0 : 1;
    }
  }
  // Both answers occur: the test exercises the proof of absence and its failures.
  EXPECT_GT(boxesSaidNo, 100);
  EXPECT_GT(boxesWithANearPoint, 100);
}

TEST(SegmentProximity, AnEmptySetIsNearNothing) {
  const SegmentProximity none;
  EXPECT_FALSE(none.near({0, 0, 0}, 1));
  Box3 box;
  box.extend(Vec3{0, 0, 0});
  box.extend(Vec3{1, 1, 1});
  EXPECT_FALSE(none.mayBeNear(box, 1));
}

}  // namespace
}  // namespace penumbra
