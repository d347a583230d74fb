#include "penumbra/spatial/uniform_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "support/scene_builder.h"

namespace penumbra {
namespace {

PosedScene randomTriangles(int count, std::uint64_t seed) {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 10), s(-0.8, 0.8);
  for (int i = 0; i < count; ++i) {
    const Vec3 c{u(rng), u(rng), u(rng)};
    b.addPolygon("white", {c + Vec3{s(rng), s(rng), s(rng)}, c + Vec3{s(rng), s(rng), s(rng)},
                           c + Vec3{s(rng), s(rng), s(rng)}});
  }
  return b.pose();
}

TEST(UniformGrid, ResolutionFollowsPolygonCountAndShape) {
  Box3 box;
  box.extend({0, 0, 0});
  box.extend({8, 2, 4});
  const GridResolution r = UniformGrid::chooseResolution(box, 1000);
  EXPECT_NEAR(double(r.cellCount()), 1000 * UniformGrid::kCellsPerPolygon, 400);
  EXPECT_GT(r.nx, r.nz);
  EXPECT_GT(r.nz, r.ny);
  EXPECT_LE(UniformGrid::chooseResolution(box, 1).cellCount(), 2);  // near-cubic cells: 2x1x1
}

TEST(UniformGrid, CellsListExactlyThePolygonsThatCutThem) {
  const PosedScene scene = randomTriangles(300, 1);
  const UniformGrid grid(scene, GridResolution{6, 5, 4});
  for (int cell = 0; cell < grid.resolution().cellCount(); ++cell) {
    const Box3 box = grid.cellBounds(cell);
    std::vector<PolygonId> expected;
    for (const WorldPolygon& p : scene.polygons)
      if (polygonCutsBox(p.vertices, box)) expected.push_back(p.id);
    EXPECT_EQ(grid.polygonsInCell(cell), expected) << "cell " << cell;
  }
}

TEST(UniformGrid, PolygonCutsBoxAgreesWithDenseSampling) {
  // A triangle whose bounding box overlaps a cell but which misses it: the exact clip says no.
  Box3 cell;
  cell.extend({0, 0, 0});
  cell.extend({1, 1, 1});
  EXPECT_FALSE(polygonCutsBox({{0.9, 1.5, 0.5}, {1.5, 0.9, 0.5}, {1.5, 1.5, 0.5}}, cell));
  EXPECT_TRUE(polygonCutsBox({{0.5, 1.5, 0.5}, {1.5, 0.5, 0.5}, {1.5, 1.5, 0.5}}, cell));
  // Touching a face counts (closed cells).
  EXPECT_TRUE(polygonCutsBox({{1, 0.2, 0.2}, {2, 0.2, 0.2}, {2, 0.8, 0.8}}, cell));
}

TEST(UniformGrid, SegmentVisitsExactlyTheCellsItCrosses) {
  const PosedScene scene = randomTriangles(100, 2);
  const UniformGrid grid(scene, GridResolution{7, 7, 7});
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 11);
  for (int i = 0; i < 300; ++i) {
    const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
    std::vector<int> visited = grid.cellsAlongSegment(a, b);
    // Brute force: a cell is crossed when dense samples of the segment fall inside it.
    std::vector<int> sampled;
    for (int k = 0; k <= 20000; ++k) {
      const Vec3 p = lerp(a, b, k / 20000.0);
      for (int cell : grid.cellsOverlappingBox(Box3{p, p}))
        if (grid.cellBounds(cell).contains(p)) sampled.push_back(cell);
    }
    std::sort(sampled.begin(), sampled.end());
    sampled.erase(std::unique(sampled.begin(), sampled.end()), sampled.end());
    std::vector<int> sortedVisited = visited;
    std::sort(sortedVisited.begin(), sortedVisited.end());
    // Every sampled cell is visited (the walk may add cells the samples stepped over at corners).
    EXPECT_TRUE(std::includes(sortedVisited.begin(), sortedVisited.end(), sampled.begin(),
                              sampled.end()))
        << "segment " << a << " " << b;
    // Consecutive cells of the walk are face neighbours.
    for (size_t k = 1; k < visited.size(); ++k) {
      const auto p = grid.cellCoordinates(visited[k - 1]), q = grid.cellCoordinates(visited[k]);
      EXPECT_EQ(std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]), 1);
    }
  }
}

TEST(UniformGrid, BoxQueryFindsEveryPolygonInTheBox) {
  const PosedScene scene = randomTriangles(400, 4);
  const UniformGrid grid(scene);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 10);
  for (int i = 0; i < 100; ++i) {
    Box3 box;
    box.extend({u(rng), u(rng), u(rng)});
    box.extend({u(rng), u(rng), u(rng)});
    const std::vector<PolygonId> found = grid.polygonsInBox(box);
    for (const WorldPolygon& p : scene.polygons) {
      if (polygonCutsBox(p.vertices, box)) {
        EXPECT_TRUE(std::binary_search(found.begin(), found.end(), p.id)) << p.id;
      }
    }
  }
}

}  // namespace
}  // namespace penumbra
