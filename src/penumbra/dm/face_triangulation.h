#pragma once
// Triangles of one face of a receiver's discontinuity mesh, for Gouraud rendering and export: a
// constrained Delaunay triangulation of the face's boundary edges (holes included), keeping every
// mesh vertex (adding none unless asked to refine). Each triangle lies inside the face, so the
// face's backprojection gives the exact irradiance at its corners.
//
// CGAL stays inside face_triangulation.cpp.

#include <array>
#include <utility>
#include <vector>

#include "penumbra/geometry/polygon.h"

namespace penumbra {

// `boundary`: the face's separating edges (ReceiverMesh::faceBoundarySegments) in the plane of
// `frame`. Triangles are counter-clockwise about frame.n. With `spacing` > 0, large faces are
// refined to about that size without T-junctions: each boundary segment is cut into equal parts
// computed from its own ends alone (so two faces sharing it cut it at the same points), and points
// of a lattice of the frame (the same for every face of a receiver) are added inside, away from
// the boundary.
std::vector<std::array<Vec3, 3>> triangulateFace(const std::vector<std::pair<Vec3, Vec3>>& boundary,
                                                 const PlaneFrame& frame, double spacing = 0);

}  // namespace penumbra
