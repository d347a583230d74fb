#include "penumbra/spatial/uniform_grid.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

GridResolution UniformGrid::chooseResolution(const Box3& bounds, int polygonCount) {
  const Vec3 d = bounds.diagonal();
  const double volume = std::max(d.x, 1e-300) * std::max(d.y, 1e-300) * std::max(d.z, 1e-300);
  const double targetCells = std::max(1.0, kCellsPerPolygon * polygonCount);
  // Cube side so that volume / side^3 ≈ targetCells; thin boxes get at least one cell per axis.
  const double side = std::cbrt(volume / targetCells);
  const auto axisCells = [&](double extent) {
    return std::clamp(int(std::lround(extent / side)), 1, kMaxCellsPerAxis);
  };
  return {axisCells(d.x), axisCells(d.y), axisCells(d.z)};
}

UniformGrid::UniformGrid(const PosedScene& scene, std::optional<GridResolution> resolution) {
  // A margin keeps polygons on the box's faces strictly inside the grid.
  bounds_ = scene.extent.expanded(1e-9 * std::max(1.0, scene.extent.diagonalLength()));
  resolution_ = resolution ? *resolution : chooseResolution(bounds_, int(scene.polygons.size()));
  const Vec3 d = bounds_.diagonal();
  cellSize_ = {d.x / resolution_.nx, d.y / resolution_.ny, d.z / resolution_.nz};
  cells_.resize(resolution_.cellCount());
  for (const WorldPolygon& polygon : scene.polygons) {
    for (int cell : cellsOverlappingBox(polygon.bounds))
      if (polygonCutsBox(polygon.vertices, cellBounds(cell))) cells_[cell].push_back(polygon.id);
  }
}

void UniformGrid::removeObject(const PosedScene& scene, int object) {
  for (PolygonId id = scene.objectFirstPolygon[object]; id < scene.objectFirstPolygon[object + 1];
       ++id)
    forEachCellOverlappingBox(scene.polygons[id].bounds, [&](int cell) {
      std::vector<PolygonId>& list = cells_[cell];
      const auto at = std::lower_bound(list.begin(), list.end(), id);
      if (at != list.end() && *at == id) list.erase(at);
    });
}

void UniformGrid::insertObject(const PosedScene& scene, int object) {
  for (PolygonId id = scene.objectFirstPolygon[object]; id < scene.objectFirstPolygon[object + 1];
       ++id) {
    const WorldPolygon& polygon = scene.polygons[id];
    forEachCellOverlappingBox(polygon.bounds, [&](int cell) {
      if (!polygonCutsBox(polygon.vertices, cellBounds(cell))) return;
      std::vector<PolygonId>& list = cells_[cell];
      // Sorted insertion keeps the list as a fresh build (which inserts in id order) makes it.
      list.insert(std::lower_bound(list.begin(), list.end(), id), id);
    });
  }
}

std::array<int, 3> UniformGrid::cellCoordinates(int cell) const {
  return {cell % resolution_.nx, (cell / resolution_.nx) % resolution_.ny,
          cell / (resolution_.nx * resolution_.ny)};
}

Box3 UniformGrid::cellBounds(int cell) const {
  const auto [ix, iy, iz] = cellCoordinates(cell);
  Box3 box;
  box.min = bounds_.min + Vec3{ix * cellSize_.x, iy * cellSize_.y, iz * cellSize_.z};
  box.max = box.min + cellSize_;
  // The last cell ends exactly at the grid's bound, whatever the rounding.
  if (ix == resolution_.nx - 1) box.max.x = bounds_.max.x;
  if (iy == resolution_.ny - 1) box.max.y = bounds_.max.y;
  if (iz == resolution_.nz - 1) box.max.z = bounds_.max.z;
  return box;
}

std::array<int, 3> UniformGrid::clampedCoordinates(const Vec3& p) const {
  const int n[3] = {resolution_.nx, resolution_.ny, resolution_.nz};
  std::array<int, 3> c{};
  for (int a = 0; a < 3; ++a) {
    const double t = (p[a] - bounds_.min[a]) / cellSize_[a];
    c[a] = std::clamp(int(std::floor(t)), 0, n[a] - 1);
  }
  return c;
}

UniformGrid::CellRange UniformGrid::cellRangeOverlapping(const Box3& box) const {
  // Expand by one cell where the box touches a cell boundary: closed-box semantics.
  std::array<int, 3> first = clampedCoordinates(box.min), last = clampedCoordinates(box.max);
  const int n[3] = {resolution_.nx, resolution_.ny, resolution_.nz};
  for (int a = 0; a < 3; ++a) {
    if (first[a] > 0 && box.min[a] <= bounds_.min[a] + first[a] * cellSize_[a]) --first[a];
    if (last[a] < n[a] - 1 && box.max[a] >= bounds_.min[a] + (last[a] + 1) * cellSize_[a])
      ++last[a];
  }
  return {first, last};
}

std::vector<int> UniformGrid::cellsOverlappingBox(const Box3& box) const {
  std::vector<int> out;
  forEachCellOverlappingBox(box, [&](int cell) { out.push_back(cell); });
  return out;
}

std::vector<int> UniformGrid::cellsAlongSegment(const Vec3& a, const Vec3& b) const {
  std::vector<int> out;
  // Clip the segment to the grid's box (slab method).
  double t0 = 0, t1 = 1;
  const Vec3 d = b - a;
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] == 0) {
      if (a[axis] < bounds_.min[axis] || a[axis] > bounds_.max[axis]) return out;
      continue;
    }
    double ta = (bounds_.min[axis] - a[axis]) / d[axis];
    double tb = (bounds_.max[axis] - a[axis]) / d[axis];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return out;
  }
  const Vec3 start = a + d * t0;
  std::array<int, 3> cell = clampedCoordinates(start);
  const std::array<int, 3> endCell = clampedCoordinates(a + d * t1);
  const int n[3] = {resolution_.nx, resolution_.ny, resolution_.nz};
  int step[3];
  double tMax[3], tDelta[3];
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] > 0) {
      step[axis] = 1;
      tMax[axis] = (bounds_.min[axis] + (cell[axis] + 1) * cellSize_[axis] - a[axis]) / d[axis];
      tDelta[axis] = cellSize_[axis] / d[axis];
    } else if (d[axis] < 0) {
      step[axis] = -1;
      tMax[axis] = (bounds_.min[axis] + cell[axis] * cellSize_[axis] - a[axis]) / d[axis];
      tDelta[axis] = -cellSize_[axis] / d[axis];
    } else {
      step[axis] = 0;
      tMax[axis] = tDelta[axis] = std::numeric_limits<double>::infinity();
    }
  }
  // Bounded walk: at most one step per cell boundary between the two end cells.
  const int maxSteps = std::abs(endCell[0] - cell[0]) + std::abs(endCell[1] - cell[1]) +
                       std::abs(endCell[2] - cell[2]) + 1;
  for (int i = 0; i < maxSteps; ++i) {
    out.push_back(cellIndex(cell[0], cell[1], cell[2]));
    if (cell == endCell) break;
    const int axis =
        tMax[0] <= tMax[1] ? (tMax[0] <= tMax[2] ? 0 : 2) : (tMax[1] <= tMax[2] ? 1 : 2);
    cell[axis] += step[axis];
    if (cell[axis] < 0 || cell[axis] >= n[axis]) break;
    tMax[axis] += tDelta[axis];
  }
  return out;
}

namespace {
std::vector<PolygonId> distinctPolygons(const std::vector<std::vector<PolygonId>>& cells,
                                        const std::vector<int>& cellIndices) {
  std::vector<PolygonId> out;
  for (int cell : cellIndices) out.insert(out.end(), cells[cell].begin(), cells[cell].end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}
}  // namespace

bool UniformGrid::listsPolygonInBox(PolygonId p, const Box3& polygonBounds, const Box3& box) const {
  if (box.isEmpty() || polygonBounds.isEmpty() || !box.overlaps(bounds_) ||
      !polygonBounds.overlaps(bounds_))
    return false;
  return listsPolygonInCells(p, cellRangeOverlapping(box), cellRangeOverlapping(polygonBounds));
}

bool UniformGrid::overlap(const CellRange& a, const CellRange& b) {
  for (int axis = 0; axis < 3; ++axis)
    if (std::max(a.first[axis], b.first[axis]) > std::min(a.second[axis], b.second[axis]))
      return false;
  return true;
}

bool UniformGrid::listsPolygonInCells(PolygonId p, const CellRange& a, const CellRange& b) const {
  // The cells of both: the overlap of the coordinate ranges.
  std::array<int, 3> first{}, last{};
  for (int axis = 0; axis < 3; ++axis) {
    first[axis] = std::max(a.first[axis], b.first[axis]);
    last[axis] = std::min(a.second[axis], b.second[axis]);
    if (first[axis] > last[axis]) return false;
  }
  for (int iz = first[2]; iz <= last[2]; ++iz)
    for (int iy = first[1]; iy <= last[1]; ++iy)
      for (int ix = first[0]; ix <= last[0]; ++ix) {
        const std::vector<PolygonId>& listed = cells_[cellIndex(ix, iy, iz)];
        if (std::find(listed.begin(), listed.end(), p) != listed.end()) return true;
      }
  return false;
}

UniformGrid::ListedPolygons::ListedPolygons(const UniformGrid& grid, const PosedScene& scene,
                                            const std::vector<PolygonId>& polygons)
    : grid_(grid), polygons_(polygons) {
  ranges_.reserve(polygons.size());
  for (PolygonId id : polygons) {
    const Box3& b = scene.polygons[size_t(id)].bounds;
    if (b.isEmpty() || !b.overlaps(grid_.bounds_)) {
      ranges_.emplace_back();
      continue;
    }
    const CellRange range = grid_.cellRangeOverlapping(b);
    ranges_.emplace_back(range);
    for (int axis = 0; axis < 3; ++axis) {
      block_.first[axis] =
          any_ ? std::min(block_.first[axis], range.first[axis]) : range.first[axis];
      block_.second[axis] =
          any_ ? std::max(block_.second[axis], range.second[axis]) : range.second[axis];
    }
    any_ = true;
  }
}

std::vector<PolygonId> UniformGrid::polygonsInBox(const Box3& box) const {
  return distinctPolygons(cells_, cellsOverlappingBox(box));
}

std::vector<PolygonId> UniformGrid::polygonsAlongSegment(const Vec3& a, const Vec3& b) const {
  return distinctPolygons(cells_, cellsAlongSegment(a, b));
}

size_t UniformGrid::totalEntries() const {
  size_t entries = 0;
  for (const auto& cell : cells_) entries += cell.size();
  return entries;
}

size_t UniformGrid::memoryBytes() const {
  size_t bytes = sizeof(*this) + cells_.capacity() * sizeof(cells_[0]);
  for (const auto& cell : cells_) bytes += cell.capacity() * sizeof(PolygonId);
  return bytes;
}

bool polygonCutsBox(const Polygon3& polygon, const Box3& box) {
  // A vertex strictly inside the box survives every clip below (each keeps the vertices on its
  // inner side, and two more points at least, one from each edge at that vertex): the answer is
  // yes without clipping. The comparisons are the clips' own signs (axis-aligned planes).
  if (polygon.size() >= 3)
    for (const Vec3& v : polygon)
      if (v.x > box.min.x && v.x < box.max.x && v.y > box.min.y && v.y < box.max.y &&
          v.z > box.min.z && v.z < box.max.z)
        return true;
  // Clipped back and forth between two buffers kept per thread: casting the discontinuity
  // surfaces asks this for every cell a surface's box meets, and a fresh loop per clip made its
  // allocations a tenth of a full computation's.
  thread_local Polygon3 a, b;
  const Polygon3* piece = &polygon;
  Polygon3* out = &a;
  for (int axis = 0; axis < 3; ++axis) {
    Vec3 normal;
    normal[axis] = 1;
    for (const Plane& plane : {Plane{normal, box.min[axis]}, Plane{-normal, -box.max[axis]}}) {
      clipByPlane(*piece, plane, *out);
      if (out->empty()) return false;
      piece = out;
      out = out == &a ? &b : &a;
    }
  }
  return true;
}

}  // namespace penumbra
