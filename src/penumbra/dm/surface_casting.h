#pragma once
// Casting a discontinuity surface through the regular grid (Loscos & Drettakis 1997 §3.1, §3.3):
// the fan, bounded by the scene's box, is traced through the cells it crosses; the polygons listed
// there are intersected with it, and the intersections are stored with the surface, before any
// visibility decision, so that a later move can tell which surfaces an object's old and new
// positions touch.

#include "penumbra/dm/discontinuity_surface.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

// The fan from the light (s = 0) to beyond the scene's box, as convex pieces: one triangle when
// the source is a light vertex, two meeting at the hinge when the hinge is a vertex.
std::vector<Polygon3> boundedFan(const CriticalFan& fan, const Box3& sceneBounds);

// Fills surface.cells and surface.intersections (the light polygon itself is not intersected).
void castSurface(DiscontinuitySurface& surface, const PosedScene& scene, const UniformGrid& grid);

// castSurface's result again after some objects moved, for a surface whose fan did not change and
// that was cast before (`surface` holds that cast): its cells are a function of its fan and the
// grid, and its cuts with the polygons that did not move are the same, so only the polygons
// flagged in `moved` (per polygon id, at their new pose) are intersected again where they are
// listed in one of its cells flagged in `movedCells` (every cell a moved object's new bounds
// overlap). The result equals castSurface's bit for bit: cuts stay in polygon order.
void recastMoved(DiscontinuitySurface& surface, const PosedScene& scene, const UniformGrid& grid,
                 const std::vector<char>& moved, const std::vector<char>& movedCells);

// The parts of polygon `p` inside the convex planar polygon `convex` (both planar): segments
// along the line where their planes meet. Empty when they are coplanar or do not meet.
// Each end says whether p's boundary crosses the plane there (else the convex polygon clipped it).
struct ConvexCut {
  Vec3 p0, p1;
  bool boundaryAt0 = true, boundaryAt1 = true;
};
std::vector<ConvexCut> intersectWithConvex(const Polygon3& p, const Polygon3& convex);

}  // namespace penumbra
