#pragma once
// The discontinuity mesh as triangles with exact irradiance at their corners, for Gouraud
// rendering (`render --method dm`) and PLY export (render/ply_writer.h). Every face of every
// receiver is triangulated without new vertices (face_triangulation.h); corners are evaluated with
// their own face's backprojection and not shared between faces, so contact (D0) discontinuities
// stay sharp while the D1/D2 ones are met exactly at the mesh edges.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/base/rgb.h"
#include "penumbra/dm/discontinuity_mesh_engine.h"

namespace penumbra {

struct IrradianceMesh {
  std::vector<Vec3> positions;
  std::vector<Rgb> irradiance;         // direct, W/m² per channel, per position
  std::vector<PolygonId> receiverOf;   // per position
  std::vector<std::uint32_t> indices;  // three per triangle, counter-clockwise seen from the front
  std::vector<std::pair<Vec3, Vec3>> edges;  // discontinuity edges (not receiver boundaries)
  // Corners where the face's backprojection is degenerate (NaN or negative: contact corners) and
  // the exact reference gave the value (irradiance_mesh.cpp, cornerIrradiance).
  long long referenceCorners = 0;
  // Faces left out: under a polygon in face-to-face contact with their receiver, seen from nowhere.
  long long coveredFaces = 0;
};

// Irradiance varies smoothly but not linearly inside a face, so triangles longer than
// `maxEdgeLength` (0: no limit) are refined (face_triangulation.h: without T-junctions), every
// corner evaluated exactly too.
IrradianceMesh buildIrradianceMesh(const DiscontinuityMeshEngine& engine, double maxEdgeLength = 0);

// The first difference between two meshes, compared bit for bit (positions, irradiance, receivers,
// triangles, edges), in words; nothing when they are identical. What `shadows --mode verify`
// compares between an updated solution and one computed from scratch.
std::optional<std::string> firstDifference(const IrradianceMesh& a, const IrradianceMesh& b);

}  // namespace penumbra
