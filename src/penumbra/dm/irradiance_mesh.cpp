#include "penumbra/dm/irradiance_mesh.h"

#include <algorithm>
#include <cmath>

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

}  // namespace penumbra
