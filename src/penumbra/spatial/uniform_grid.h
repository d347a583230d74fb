#pragma once
// The regular grid over the scene's extent (Loscos & Drettakis 1997 §3.1): each cell lists the
// polygons that cut it, sorted by id. Discontinuity surfaces are cast through the same cells, so
// cells are addressed by a stable linear index and the traversal primitives (box, segment) are
// exposed.
//
// The grid covers PosedScene::extent, every pose the scene can reach, with a resolution fixed at
// construction: a cell index means the same region at every frame, and moving an object edits only
// the lists of the cells its polygons leave and enter (removeObject / insertObject), leaving lists
// identical to those of a grid built from scratch at the new pose.

#include <array>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "penumbra/scene/posed_scene.h"

namespace penumbra {

struct GridResolution {
  int nx = 1, ny = 1, nz = 1;
  int cellCount() const { return nx * ny * nz; }
};

class UniformGrid {
 public:
  // An inclusive range of cell coordinates: its first and last cell along each axis.
  using CellRange = std::pair<std::array<int, 3>, std::array<int, 3>>;
  // About kCellsPerPolygon cells per polygon, shaped to the box so that cells are near-cubes.
  static constexpr double kCellsPerPolygon = 1.0;
  static constexpr int kMaxCellsPerAxis = 256;
  static GridResolution chooseResolution(const Box3& bounds, int polygonCount);

  // Over scene.extent; uses chooseResolution unless `resolution` is given.
  explicit UniformGrid(const PosedScene& scene, std::optional<GridResolution> resolution = {});

  // Moving an object: remove its polygons at the old pose, re-pose, insert them at the new pose.
  // Polygons outside the grid's bounds are clamped to the border cells they would enter; callers
  // keep every pose inside the extent (DynamicScene re-grids when it grows).
  void removeObject(const PosedScene& scene, int object);
  void insertObject(const PosedScene& scene, int object);

  const GridResolution& resolution() const { return resolution_; }
  const Box3& bounds() const { return bounds_; }
  int cellIndex(int ix, int iy, int iz) const {
    return ix + resolution_.nx * (iy + resolution_.ny * iz);
  }
  std::array<int, 3> cellCoordinates(int cell) const;
  Box3 cellBounds(int cell) const;
  const std::vector<PolygonId>& polygonsInCell(int cell) const { return cells_[cell]; }

  // Cells whose closed bounds overlap `box` (clamped to the grid).
  std::vector<int> cellsOverlappingBox(const Box3& box) const;
  // The same cells, visited without allocating: visit(cellIndex).
  template <typename Visit>
  void forEachCellOverlappingBox(const Box3& box, Visit&& visit) const {
    if (box.isEmpty() || !box.overlaps(bounds_)) return;
    const auto [first, last] = cellRangeOverlapping(box);
    for (int iz = first[2]; iz <= last[2]; ++iz)
      for (int iy = first[1]; iy <= last[1]; ++iy)
        for (int ix = first[0]; ix <= last[0]; ++ix) visit(cellIndex(ix, iy, iz));
  }
  // Is polygon p (whose bounds are `polygonBounds`: it is listed only in cells overlapping them)
  // listed in some cell overlapping `box`, as polygonsInBox(box) would find it?
  bool listsPolygonInBox(PolygonId p, const Box3& polygonBounds, const Box3& box) const;
  // The same question for a few polygons (a moved object's) asked of many boxes: the polygons of
  // `polygons` listed in some cell overlapping `box`, in their order, each as listsPolygonInBox
  // answers; a box whose cells lie outside the block of cells all of them overlap is answered
  // with one test. Most boxes a large room's update asks about lie far from what moved.
  class ListedPolygons {
   public:
    ListedPolygons(const UniformGrid& grid, const PosedScene& scene,
                   const std::vector<PolygonId>& polygons);
    template <typename Visit>
    void forEachListedInBox(const Box3& box, Visit&& visit) const {
      if (!any_ || box.isEmpty() || !box.overlaps(grid_.bounds_)) return;
      // One range for the box; none of the polygons where it misses the block holding theirs.
      const CellRange range = grid_.cellRangeOverlapping(box);
      if (!overlap(range, block_)) return;
      for (size_t k = 0; k < polygons_.size(); ++k)
        if (ranges_[k] && grid_.listsPolygonInCells(polygons_[k], range, *ranges_[k]))
          visit(polygons_[k]);
    }

   private:
    const UniformGrid& grid_;
    const std::vector<PolygonId>& polygons_;  // the caller's: it outlives this
    // Each polygon's cells, in their order; none where listsPolygonInBox answers false whatever
    // the box (bounds empty or off the grid).
    std::vector<std::optional<CellRange>> ranges_;
    bool any_ = false;  // some polygon has cells
    CellRange block_;   // the block of cells holding all of them
  };
  // Cells the closed segment ab passes through, in order from a (3D DDA, Amanatides & Woo 1987);
  // the parts of the segment outside the grid are ignored.
  std::vector<int> cellsAlongSegment(const Vec3& a, const Vec3& b) const;
  // Distinct polygons listed in the cells overlapping `box`, sorted by id.
  std::vector<PolygonId> polygonsInBox(const Box3& box) const;
  // Distinct polygons listed in the cells along the segment, sorted by id.
  std::vector<PolygonId> polygonsAlongSegment(const Vec3& a, const Vec3& b) const;

  // Memory held by the per-cell lists (bytes), for reports.
  size_t memoryBytes() const;
  size_t totalEntries() const;

 private:
  std::array<int, 3> clampedCoordinates(const Vec3& p) const;
  // Inclusive cell coordinate range of the cells overlapping a box that overlaps the grid.
  CellRange cellRangeOverlapping(const Box3& box) const;
  // Do two cell ranges share a cell?
  static bool overlap(const CellRange& a, const CellRange& b);
  // Is polygon p listed in a cell of both ranges (listsPolygonInBox, the ranges of its boxes)?
  bool listsPolygonInCells(PolygonId p, const CellRange& a, const CellRange& b) const;

  GridResolution resolution_;
  Box3 bounds_;
  Vec3 cellSize_;
  std::vector<std::vector<PolygonId>> cells_;
};

// Whether a polygon has a point in the closed box (clips the polygon to the box's six planes).
bool polygonCutsBox(const Polygon3& polygon, const Box3& box);

}  // namespace penumbra
