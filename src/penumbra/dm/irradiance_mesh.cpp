#include "penumbra/dm/irradiance_mesh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>

#include "penumbra/dm/face_triangulation.h"

namespace penumbra {

IrradianceMesh buildIrradianceMesh(const DiscontinuityMeshEngine& engine, double maxEdgeLength) {
  IrradianceMesh out;
  const PosedScene& scene = engine.posedScene();
  for (const WorldPolygon& receiver : scene.polygons) {
    const ReceiverMesh* mesh = engine.meshOf(receiver.id);
    if (!mesh) continue;
    for (const MeshFace& face : mesh->faces()) {
      for (const auto& triangle :
           triangulateFace(mesh->faceBoundarySegments(face.index), mesh->frame())) {
        // Counter-clockwise about the frame's normal; the frame's normal is the receiver's.
        const auto& [a, b, c] = triangle;
        const double longest = std::max({distance(a, b), distance(b, c), distance(c, a)});
        const int splits =
            maxEdgeLength > 0 ? std::clamp(int(std::ceil(longest / maxEdgeLength)), 1, 64) : 1;
        // Barycentric grid: row i, column j ↦ a + (b − a) i/k + (c − a) j/k.
        const auto first = std::uint32_t(out.positions.size());
        const auto index = [&](int i, int j) {
          return first + std::uint32_t(i * (2 * splits + 3 - i) / 2 + j);
        };
        for (int i = 0; i <= splits; ++i)
          for (int j = 0; i + j <= splits; ++j) {
            const Vec3 p = a + (b - a) * (double(i) / splits) + (c - a) * (double(j) / splits);
            out.positions.push_back(p);
            out.irradiance.push_back(engine.faceIrradianceAt(receiver.id, face.index, p));
            out.receiverOf.push_back(receiver.id);
          }
        for (int i = 0; i < splits; ++i)
          for (int j = 0; i + j < splits; ++j) {
            out.indices.insert(out.indices.end(), {index(i, j), index(i + 1, j), index(i, j + 1)});
            if (i + j + 1 < splits)
              out.indices.insert(out.indices.end(),
                                 {index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)});
          }
      }
    }
    for (const auto& [segment, surfaces] : mesh->edges())
      if (!surfaces.empty() && surfaces.front() != ReceiverMesh::kBoundary)
        out.edges.push_back(segment);
  }
  return out;
}

namespace {

// Bit for bit: -0 differs from 0, and a NaN equals the same NaN (a NaN is a defect of its own,
// issue 20, but not a difference between two computations).
bool identical(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}
bool identical(const Vec3& a, const Vec3& b) {
  return identical(a.x, b.x) && identical(a.y, b.y) && identical(a.z, b.z);
}
bool identical(const Rgb& a, const Rgb& b) {
  return identical(a.r, b.r) && identical(a.g, b.g) && identical(a.b, b.b);
}

std::string describe(const Vec3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.17g, %.17g, %.17g)", v.x, v.y, v.z);
  return text;
}

}  // namespace

std::optional<std::string> firstDifference(const IrradianceMesh& a, const IrradianceMesh& b) {
  if (a.positions.size() != b.positions.size())
    return "corner counts differ: " + std::to_string(a.positions.size()) + " vs " +
           std::to_string(b.positions.size());
  if (a.indices.size() != b.indices.size())
    return "triangle counts differ: " + std::to_string(a.indices.size() / 3) + " vs " +
           std::to_string(b.indices.size() / 3);
  if (a.edges.size() != b.edges.size())
    return "edge counts differ: " + std::to_string(a.edges.size()) + " vs " +
           std::to_string(b.edges.size());
  for (size_t i = 0; i < a.positions.size(); ++i) {
    if (!identical(a.positions[i], b.positions[i]) || a.receiverOf[i] != b.receiverOf[i])
      return "corner " + std::to_string(i) + " differs: " + describe(a.positions[i]) + " vs " +
             describe(b.positions[i]);
    if (!identical(a.irradiance[i], b.irradiance[i]))
      return "irradiance at corner " + std::to_string(i) + " " + describe(a.positions[i]) +
             " on polygon " + std::to_string(a.receiverOf[i]) + " differs";
  }
  for (size_t i = 0; i < a.indices.size(); ++i)
    if (a.indices[i] != b.indices[i]) return "triangle " + std::to_string(i / 3) + " differs";
  for (size_t i = 0; i < a.edges.size(); ++i)
    if (!identical(a.edges[i].first, b.edges[i].first) ||
        !identical(a.edges[i].second, b.edges[i].second))
      return "discontinuity edge " + std::to_string(i) + " differs: " + describe(a.edges[i].first) +
             " vs " + describe(b.edges[i].first);
  return std::nullopt;
}

}  // namespace penumbra
