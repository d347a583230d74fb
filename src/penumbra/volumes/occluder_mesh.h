#pragma once
// The edge adjacency of one scene object, as a shadow-volume occluder needs it (McReynolds &
// Blythe, Advanced Graphics Programming Techniques Using OpenGL, §11.3.2.3): vertices welded by
// exact equality of object-space coordinates, each polygon as a ring of vertex indices, its
// triangulation (the caps), and for every polygon edge the polygon that shares it in the opposite
// direction, if any.
//
// Built once per object in object space, so the adjacency never changes while the object moves.

#include <array>
#include <vector>

#include "penumbra/geometry/polygon.h"

namespace penumbra {

struct OccluderMesh {
  std::vector<Vec3> vertices;                              // object space, welded
  std::vector<std::vector<int>> polygons;                  // vertex indices, input winding
  std::vector<std::vector<std::array<int, 3>>> triangles;  // per polygon, vertex indices
  // neighbor[p][i]: the polygon that uses edge (polygons[p][i], polygons[p][i+1]) in the opposite
  // direction when exactly one other polygon uses that edge at all; -1 otherwise (boundary edge,
  // non-manifold edge, or inconsistently oriented neighbours).
  std::vector<std::vector<int>> neighbor;
  // Every edge has an opposite-direction neighbour: a closed, consistently oriented surface.
  bool isClosed = false;
};

// Precondition: each polygon has >= 3 vertices (the scene loader guarantees it).
OccluderMesh buildOccluderMesh(const std::vector<Polygon3>& objectPolygons);

}  // namespace penumbra
