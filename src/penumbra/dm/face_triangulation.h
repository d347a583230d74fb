#pragma once
// Triangles of one face of a receiver's discontinuity mesh, for Gouraud rendering and export: a
// constrained Delaunay triangulation of the face's boundary edges (holes included), keeping every
// mesh vertex and adding none. Each triangle lies inside the face, so the face's backprojection
// gives the exact irradiance at its corners.
//
// CGAL stays inside face_triangulation.cpp.

#include <array>
#include <utility>
#include <vector>

#include "penumbra/geometry/polygon.h"

namespace penumbra {

// `boundary`: the face's separating edges (ReceiverMesh::faceBoundarySegments) in the plane of
// `frame`. Triangles are counter-clockwise about frame.n.
std::vector<std::array<Vec3, 3>> triangulateFace(const std::vector<std::pair<Vec3, Vec3>>& boundary,
                                                 const PlaneFrame& frame);

}  // namespace penumbra
