#pragma once
// Bounds of runs of consecutive vertices of a polygon with many vertices (a finely tessellated
// disc or cap), so that clipping it and searching its features near a small cone skip whole runs
// instead of visiting every vertex: the cost then follows the part of the polygon that matters.

#include <span>
#include <utility>
#include <vector>

#include "penumbra/geometry/box.h"
#include "penumbra/geometry/plane.h"
#include "penumbra/geometry/polygon.h"

namespace penumbra {

// Vertices [begin, end) of a loop, all inside `box`.
struct VertexRun {
  size_t begin = 0, end = 0;
  Box3 box;
};

inline constexpr size_t kVertexRun = 16;

// Runs of kVertexRun vertices covering the whole loop, each box also holding the vertex after the
// run, so that it bounds the run's edges too. Empty for a polygon of at most two runs' worth of
// vertices: visiting its vertices is as cheap.
std::vector<VertexRun> edgeRuns(const Polygon3& polygon);

// The range of plane.signedDistance over the box, widened to cover the rounding of evaluating it
// at any point of the box: a box whose range lies below zero holds only points whose computed
// distance is negative, so skipping its points decides exactly as evaluating each would.
std::pair<double, double> signedDistanceRange(const Plane& plane, const Box3& box);

// clipByPlane(polygon, plane, out), bit for bit, skipping runs wholly behind the plane and
// copying runs wholly in front of it. `runs` are disjoint and in order (or empty); `outRuns`
// receives the copied runs, placed in `out`, for clipping `out` by the next plane alike.
void clipByPlane(const Polygon3& polygon, std::span<const VertexRun> runs, const Plane& plane,
                 Polygon3& out, std::vector<VertexRun>& outRuns);

}  // namespace penumbra
