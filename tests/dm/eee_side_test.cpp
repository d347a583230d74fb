#include <gtest/gtest.h>

#include <cmath>
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

}  // namespace
}  // namespace penumbra
