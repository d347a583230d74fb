#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <random>

#include "penumbra/dm/eee_surfaces.h"
#include "support/scene_builder.h"

namespace penumbra {
namespace {

// Three cards whose first edges lie on three skew lines: L1 = (t, 0, 1), L2 = (0, s, 2) and
// L3 = (1, 1, u). The transversal through (2, 0, 1) and (0, 2, 2) meets L3 at (1, 1, 1.5) and the
// floor z = 0 at (4, -2, 0): that point lies exactly on the quadric of the three lines.
struct ThreeSkewEdges {
  PosedScene scene;
  EdgeAdjacency adjacency;
  EeeSurface surface;

  static PosedScene make() {
    test::SceneBuilder b;
    b.addMaterial("white", {0.5, 0.5, 0.5});
    b.addPolygon("white", {{-1, 0, 1}, {3, 0, 1}, {1, -0.5, 1}});
    b.addPolygon("white", {{0, -1, 2}, {0, 3, 2}, {-0.5, 1, 2}});
    b.addPolygon("white", {{1, 1, 0.5}, {1, 1, 2.5}, {1.5, 1.2, 1.5}});
    return b.pose();
  }
  ThreeSkewEdges() : scene(make()), adjacency(scene) {
    const auto firstEdge = [&](PolygonId p) {
      const std::vector<VertexId>& corners = adjacency.polygonVertices(p);
      return adjacency.edgeBetween(corners[0], corners[1]);
    };
    surface.kind = EeeKind::kOccluderEdges;
    surface.first = firstEdge(0);
    surface.second = firstEdge(1);
    surface.third = firstEdge(2);
  }
};

TEST(EeeSide, ExactSignIsZeroOnTheQuadricAndFlipsAcrossIt) {
  const ThreeSkewEdges s;
  ASSERT_GE(s.surface.first, 0);
  ASSERT_GE(s.surface.second, 0);
  ASSERT_GE(s.surface.third, 0);
  const Vec3 on{4, -2, 0};
  EXPECT_EQ(exactEeeSideSign(s.surface, s.scene, s.adjacency, on), 0);
  // One ulp either way along x: the rounded value cannot tell (it is within its rounding of 0),
  // the exact sign can, and it differs on the two sides.
  const Vec3 below{std::nextafter(4.0, 0.0), -2, 0}, above{std::nextafter(4.0, 8.0), -2, 0};
  const auto signBelow = exactEeeSideSign(s.surface, s.scene, s.adjacency, below);
  const auto signAbove = exactEeeSideSign(s.surface, s.scene, s.adjacency, above);
  ASSERT_TRUE(signBelow && signAbove);
  EXPECT_NE(*signBelow, 0);
  EXPECT_EQ(*signBelow, -*signAbove);
  EXPECT_LE(std::abs(eeeSide(s.surface, s.scene, s.adjacency, below)), 1e-11);
}

TEST(EeeSide, ExactSignAgreesWithTheRoundedValueWhereThatIsCertain) {
  const ThreeSkewEdges s;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-6, 6);
  int compared = 0, positive = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 p{u(rng), u(rng), 0};
    const double rounded = eeeSide(s.surface, s.scene, s.adjacency, p);
    if (!(std::abs(rounded) > 1e-9)) continue;
    const auto exact = exactEeeSideSign(s.surface, s.scene, s.adjacency, p);
    ASSERT_TRUE(exact);
    EXPECT_EQ(*exact, rounded > 0 ? 1 : -1) << p.x << " " << p.y;
    ++compared;
    positive += rounded > 0 ? 1 : 0;
  }
  EXPECT_GT(compared, 1900);
  EXPECT_GT(positive, 100);  // both sides visited
  EXPECT_LT(positive, compared - 100);
}

// The sign changes of the exact side sign along a to b, sampled at 1,024 steps (from step
// `first`); nothing where it is undefined or zero at a sample.
std::optional<int> sampledSignChanges(const ThreeSkewEdges& s, const Vec3& a, const Vec3& b,
                                      int first) {
  constexpr int kSteps = 1024;
  int changes = 0;
  std::optional<int> previous;
  for (int i = first; i <= kSteps; ++i) {
    const auto sign =
        exactEeeSideSign(s.surface, s.scene, s.adjacency, a + (b - a) * (double(i) / kSteps));
    if (!sign || *sign == 0) return std::nullopt;
    if (previous && *previous != *sign) ++changes;
    previous = sign;
  }
  return changes;
}

// eeeQuadricCrossings against the exact side sign sampled densely along the segment (sign changes
// counted over 1,024 steps): random segments of the floor, where the quadric's conic is a
// hyperbola, so that a segment may cross it twice with equal sides at its ends.
TEST(EeeQuadricCrossings, CountsTheSignChangesAlongTheSegment) {
  const ThreeSkewEdges s;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-6, 6);
  int compared = 0, uncertain = 0;
  std::array<int, 3> byCount{};
  for (int k = 0; k < 300; ++k) {
    const Vec3 a{u(rng), u(rng), 0}, b{u(rng), u(rng), 0};
    const std::optional<int> sampled = sampledSignChanges(s, a, b, 0);
    if (!sampled) continue;
    const int changes = *sampled;
    const std::optional<int> counted = eeeQuadricCrossings(s.surface, s.scene, s.adjacency, a, b);
    if (!counted) {
      ++uncertain;
      continue;
    }
    ASSERT_LE(changes, 2) << "a quadric's conic meets a line at most twice";
    EXPECT_EQ(*counted, changes) << a.x << " " << a.y << " to " << b.x << " " << b.y;
    ++compared;
    ++byCount[size_t(changes)];
  }
  std::printf(
      "[ info     ] %d segments compared (%d, %d, %d crossing 0, 1, 2 times), %d uncertain\n",
      compared, byCount[0], byCount[1], byCount[2], uncertain);
  EXPECT_GT(compared, 250);
  EXPECT_LE(uncertain, 3);
  EXPECT_GT(byCount[0], 20);
  EXPECT_GT(byCount[1], 20);
  EXPECT_GT(byCount[2], 20);
}

// From a point on the quadric (its side unknown in doubles), the crossing there is not counted;
// the segment's other crossing is, when it has one.
TEST(EeeQuadricCrossings, LeaveOutTheCrossingAtAStartOnTheQuadric) {
  const ThreeSkewEdges s;
  const Vec3 on{4, -2, 0};
  int withOther = 0, without = 0;
  for (int d = 0; d < 64; ++d) {
    const double angle = d * std::numbers::pi / 32 + 0.05;
    const Vec3 b = on + Vec3{std::cos(angle), std::sin(angle), 0} * 3;
    const std::optional<int> sampled = sampledSignChanges(s, on, b, 1);
    if (!sampled) continue;
    const int changes = *sampled;
    const std::optional<int> counted = eeeQuadricCrossings(s.surface, s.scene, s.adjacency, on, b);
    if (!counted) continue;
    EXPECT_EQ(*counted, changes) << "towards " << angle;
    ++(changes ? withOther : without);
  }
  EXPECT_GT(withOther, 4);
  EXPECT_GT(without, 20);
}

}  // namespace
}  // namespace penumbra
