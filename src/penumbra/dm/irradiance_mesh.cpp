#include "penumbra/dm/irradiance_mesh.h"

#include "penumbra/dm/face_triangulation.h"

namespace penumbra {

IrradianceMesh buildIrradianceMesh(const DiscontinuityMeshEngine& engine) {
  IrradianceMesh out;
  const PosedScene& scene = engine.posedScene();
  for (const WorldPolygon& receiver : scene.polygons) {
    const ReceiverMesh* mesh = engine.meshOf(receiver.id);
    if (!mesh) continue;
    for (const MeshFace& face : mesh->faces()) {
      for (const auto& triangle :
           triangulateFace(mesh->faceBoundarySegments(face.index), mesh->frame())) {
        // Counter-clockwise about the frame's normal; the frame's normal is the receiver's.
        for (const Vec3& corner : triangle) {
          out.indices.push_back(std::uint32_t(out.positions.size()));
          out.positions.push_back(corner);
          out.irradiance.push_back(engine.faceIrradianceAt(receiver.id, face.index, corner));
          out.receiverOf.push_back(receiver.id);
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
