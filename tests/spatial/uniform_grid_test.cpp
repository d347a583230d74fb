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

TEST(UniformGrid, PolygonCutsBoxAnswersAsTheClipAlone) {
  // polygonCutsBox answers yes without clipping where a vertex lies strictly inside the box. The
  // clip alone (the six planes, each through clipByPlane) is the reference: every answer must be
  // the same, for polygons around, inside, on and beside a box, vertices on its faces, edges and
  // corners, and degenerate loops (two vertices, repeated points).
  Box3 box;
  box.extend({0, 0, 0});
  box.extend({1, 2, 0.5});
  const auto byClipping = [&](const Polygon3& polygon) {
    Polygon3 piece = polygon, next;
    for (int axis = 0; axis < 3; ++axis) {
      Vec3 normal;
      normal[axis] = 1;
      for (const Plane& plane : {Plane{normal, box.min[axis]}, Plane{-normal, -box.max[axis]}}) {
        clipByPlane(piece, plane, next);
        if (next.empty()) return false;
        piece = next;
      }
    }
    return true;
  };
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.25, 1.25);
  std::uniform_int_distribution<int> pick(0, 4), size(2, 5);
  // A coordinate: random, or on one of the box's planes along that axis.
  const auto coordinate = [&](int axis) {
    switch (pick(rng)) {
      case 0:
        return box.min[axis];
      case 1:
        return box.max[axis];
      default:
        return u(rng) * (box.max[axis] - box.min[axis]);
    }
  };
  int yes = 0, no = 0, quick = 0;
  for (int i = 0; i < 20000; ++i) {
    Polygon3 polygon;
    const int n = size(rng);
    for (int k = 0; k < n; ++k) {
      if (k > 0 && pick(rng) == 0) {
        polygon.push_back(polygon.back());  // a repeated point
        continue;
      }
      polygon.push_back({coordinate(0), coordinate(1), coordinate(2)});
    }
    const bool expected = byClipping(polygon);
    ASSERT_EQ(polygonCutsBox(polygon, box), expected) << "polygon " << i;
    (expected ? yes : no)++;
    quick += polygon.size() >= 3 && std::any_of(polygon.begin(), polygon.end(), [&](const Vec3& v) {
               return v.x > box.min.x && v.x < box.max.x && v.y > box.min.y && v.y < box.max.y &&
                      v.z > box.min.z && v.z < box.max.z;
             });
  }
  // Both answers, and the shortcut taken, occur many times.
  EXPECT_GT(yes, 2000);
  EXPECT_GT(no, 2000);
  EXPECT_GT(quick, 1000);
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
    EXPECT_TRUE(
        std::includes(sortedVisited.begin(), sortedVisited.end(), sampled.begin(), sampled.end()))
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

// Triangles and planar quads (parallelograms) of random sizes and orientations, some of them
// axis-aligned, one object each.
void addTrianglesAndQuads(test::SceneBuilder& b, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 10), s(-1.5, 1.5);
  for (int i = 0; i < count; ++i) {
    const Vec3 c{u(rng), u(rng), u(rng)};
    const Vec3 e{s(rng), s(rng), s(rng)}, f{s(rng), s(rng), s(rng)};
    switch (i % 4) {
      case 0:
        b.addPolygon("white", {c, c + e, c + f});
        break;
      case 1:
        b.addPolygon("white", {c - e - f, c + e - f, c + e + f, c - e + f});
        break;
      case 2:  // axis-aligned quad in a plane z = const
        b.addPolygon("white", {c, c + Vec3{e.x, 0, 0}, c + Vec3{e.x, f.y, 0}, c + Vec3{0, f.y, 0}});
        break;
      default:  // a thin sliver
        b.addPolygon("white", {c, c + e, c + e * 0.5 + f * 1e-3});
        break;
    }
  }
}

PosedScene randomTrianglesAndQuads(int count, std::uint64_t seed) {
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  addTrianglesAndQuads(b, count, seed);
  return b.pose();
}

// Boxes for grid queries: empty ones, ones outside the grid or touching it from outside, cells and
// boxes inside one cell, point and flat boxes, boxes whose faces lie on cell boundaries, polygon
// bounds and boxes touching them, the whole grid and random boxes.
std::vector<Box3> queryBoxes(const PosedScene& scene, const UniformGrid& grid, std::uint64_t seed) {
  const auto boxOf = [](const Vec3& p, const Vec3& q) {
    Box3 box;
    box.extend(p);
    box.extend(q);
    return box;
  };
  const Box3 g = grid.bounds();
  const Vec3 one{1, 1, 1};
  std::vector<Box3> boxes;
  boxes.push_back(Box3{});
  Box3 inverted = g;
  std::swap(inverted.min.y, inverted.max.y);
  boxes.push_back(inverted);
  boxes.push_back(g);
  boxes.push_back(scene.extent);
  boxes.push_back(g.expanded(100));
  boxes.push_back(boxOf(g.max + one, g.max + one * 3));
  boxes.push_back(boxOf(g.min - one * 3, g.min - one));
  boxes.push_back(boxOf(g.min - one, g.min));                        // touches the grid's corner
  boxes.push_back(boxOf(g.min - one, {g.min.x, g.max.y, g.max.z}));  // touches its face x = min
  boxes.push_back(boxOf(g.max, g.max + one));
  boxes.push_back(boxOf({g.min.x, g.min.y, g.max.z + 1e-6}, g.max + one));  // just outside
  for (int cell = 0; cell < grid.resolution().cellCount(); ++cell) {
    const Box3 c = grid.cellBounds(cell);
    boxes.push_back(c);  // touches its neighbours too
    const Vec3 m = c.center(), q = c.diagonal() * 0.25;
    boxes.push_back(boxOf(m - q, m + q));  // strictly inside one cell
    boxes.push_back(boxOf(m, m));
    boxes.push_back(boxOf(c.min, c.min));  // a cell corner
    boxes.push_back(boxOf({c.min.x, m.y - q.y, m.z - q.z}, {c.min.x, m.y + q.y, m.z + q.z}));
  }
  for (const WorldPolygon& p : scene.polygons) {
    boxes.push_back(p.bounds);
    boxes.push_back(boxOf(p.bounds.max, p.bounds.max + one));  // touches its bounds' corner
    boxes.push_back(boxOf(p.bounds.min - one * 0.5, p.bounds.min));
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-2, 12);
  std::uniform_int_distribution<int> anyCell(0, grid.resolution().cellCount() - 1);
  for (int i = 0; i < 300; ++i) {
    boxes.push_back(boxOf({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}));
    // Faces on cell boundaries.
    boxes.push_back(boxOf(grid.cellBounds(anyCell(rng)).min, grid.cellBounds(anyCell(rng)).max));
    // Flat in one axis.
    Box3 flat = boxOf({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)});
    flat.max[i % 3] = flat.min[i % 3];
    boxes.push_back(flat);
  }
  return boxes;
}

void expectListsPolygonInBoxAgreesWithBoxQuery(const PosedScene& scene, const UniformGrid& grid,
                                               std::uint64_t seed) {
  int failures = 0, listed = 0, notListed = 0;
  // A few polygons asked together (as an update asks for a moved object's): runs of one to five
  // consecutive ids, in a shuffled order, the empty set among them.
  std::mt19937_64 rng(seed);
  std::vector<std::vector<PolygonId>> groups{{}};
  for (PolygonId first = 0; size_t(first) < scene.polygons.size();) {
    const PolygonId end =
        std::min(PolygonId(scene.polygons.size()),
                 first + PolygonId(std::uniform_int_distribution<int>(1, 5)(rng)));
    std::vector<PolygonId> group;
    for (PolygonId id = first; id < end; ++id) group.push_back(id);
    std::shuffle(group.begin(), group.end(), rng);
    groups.push_back(std::move(group));
    first = end;
  }
  std::vector<UniformGrid::ListedPolygons> asked;
  for (const std::vector<PolygonId>& group : groups) asked.emplace_back(grid, scene, group);
  int groupsListedNone = 0, groupsListed = 0;
  for (const Box3& box : queryBoxes(scene, grid, seed)) {
    const std::vector<PolygonId> found = grid.polygonsInBox(box);
    for (const WorldPolygon& p : scene.polygons) {
      const bool expected = std::binary_search(found.begin(), found.end(), p.id);
      (expected ? listed : notListed) += 1;
      if (grid.listsPolygonInBox(p.id, p.bounds, box) != expected && ++failures <= 10)
        ADD_FAILURE() << "polygon " << p.id << " box " << box.min << " " << box.max << " expected "
                      << expected;
    }
    for (size_t g = 0; g < groups.size(); ++g) {
      std::vector<PolygonId> expected, got;
      for (PolygonId id : groups[g])
        if (std::binary_search(found.begin(), found.end(), id)) expected.push_back(id);
      asked[g].forEachListedInBox(box, [&](PolygonId id) { got.push_back(id); });
      (expected.empty() ? groupsListedNone : groupsListed) += 1;
      if (got != expected && ++failures <= 10)
        ADD_FAILURE() << "group " << g << " box " << box.min << " " << box.max << ": " << got.size()
                      << " listed, expected " << expected.size();
    }
  }
  EXPECT_EQ(failures, 0);
  // Both answers are common.
  EXPECT_GT(listed, 1000);
  EXPECT_GT(notListed, 1000);
  EXPECT_GT(groupsListed, 100);
  EXPECT_GT(groupsListedNone, 100);
}

TEST(UniformGrid, ListsPolygonInBoxAgreesWithBoxQuery) {
  const PosedScene scene = randomTrianglesAndQuads(40, 6);
  expectListsPolygonInBoxAgreesWithBoxQuery(scene, UniformGrid(scene), 7);
  expectListsPolygonInBoxAgreesWithBoxQuery(scene, UniformGrid(scene, GridResolution{5, 4, 3}), 8);
  expectListsPolygonInBoxAgreesWithBoxQuery(scene, UniformGrid(scene, GridResolution{1, 1, 1}), 9);
  expectListsPolygonInBoxAgreesWithBoxQuery(scene, UniformGrid(scene, GridResolution{9, 1, 7}), 10);
}

TEST(UniformGrid, ListsPolygonInBoxAgreesForPolygonsOnCellBoundaries) {
  // The same random polygons plus polygons lying on cell faces or touching cell corners, with the
  // grid's extent and resolution unchanged, so that the cell boundaries computed from the first
  // grid are those of the second.
  const GridResolution resolution{4, 5, 3};
  const PosedScene plain = randomTrianglesAndQuads(36, 12);
  const UniformGrid plainGrid(plain, resolution);
  test::SceneBuilder b;
  b.addMaterial("white", {0.5, 0.5, 0.5});
  addTrianglesAndQuads(b, 36, 12);
  // Interior cells (below the grid's upper bounds in x and y, which are outside the extent).
  for (int ix = 1; ix + 1 < resolution.nx; ++ix)
    for (int iy = 1; iy + 1 < resolution.ny; ++iy)
      for (int iz = 1; iz < resolution.nz; ++iz) {
        const Box3 c = plainGrid.cellBounds(plainGrid.cellIndex(ix, iy, iz));
        const Vec3 d = c.diagonal();
        // The cell's lower z face, exactly.
        b.addPolygon("white", {c.min,
                               {c.max.x, c.min.y, c.min.z},
                               {c.max.x, c.max.y, c.min.z},
                               {c.min.x, c.max.y, c.min.z}});
        // A triangle below and beside the cell, touching it at its lower corner only.
        b.addPolygon("white", {c.min, c.min - Vec3{0.3 * d.x, 0.1 * d.y, 0.2 * d.z},
                               c.min - Vec3{0.1 * d.x, 0.4 * d.y, 0.3 * d.z}});
        // A triangle whose bounds end on the cell's upper x face.
        b.addPolygon("white", {{c.max.x, c.min.y + 0.5 * d.y, c.min.z + 0.5 * d.z},
                               c.min + d * 0.5,
                               c.min + Vec3{0.7 * d.x, 0.9 * d.y, 0.2 * d.z}});
      }
  PosedScene scene = b.pose();
  ASSERT_GT(scene.polygons.size(), plain.polygons.size());
  // The same extent (it contains the added polygons): the same grid bounds and cell boundaries.
  ASSERT_TRUE(plain.extent.contains(scene.bounds.min) && plain.extent.contains(scene.bounds.max));
  scene.extent = plain.extent;
  const UniformGrid grid(scene, resolution);
  ASSERT_EQ(grid.bounds().min, plainGrid.bounds().min);
  ASSERT_EQ(grid.bounds().max, plainGrid.bounds().max);
  expectListsPolygonInBoxAgreesWithBoxQuery(scene, grid, 13);
}

TEST(UniformGrid, ListsPolygonInBoxIsFalseForEmptyBoxes) {
  const PosedScene scene = randomTrianglesAndQuads(24, 11);
  const UniformGrid grid(scene, GridResolution{4, 4, 4});
  Box3 flipped = grid.bounds();
  std::swap(flipped.min.z, flipped.max.z);
  for (const WorldPolygon& p : scene.polygons) {
    EXPECT_FALSE(grid.listsPolygonInBox(p.id, p.bounds, Box3{}));
    EXPECT_FALSE(grid.listsPolygonInBox(p.id, p.bounds, flipped));
    // Its own bounds always find it: it cuts some cell they overlap.
    EXPECT_TRUE(grid.listsPolygonInBox(p.id, p.bounds, p.bounds)) << p.id;
  }
}

}  // namespace
}  // namespace penumbra
