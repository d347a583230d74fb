#include "penumbra/radiosity/combined_solution.h"

#include "penumbra/spatial/dynamic_scene.h"

namespace penumbra {

namespace {

RadiosityOptions withExactDirect(RadiosityOptions options, const DiscontinuityMeshEngine& dm) {
  // The mesh locates the point's receiver itself; a point it does not answer (a lamp's own
  // polygon, which the mesh does not receive on) keeps radiosity's gathered direct part.
  options.exactDirect = [&dm](const Vec3& p, const Vec3& n, PolygonId) {
    return dm.irradiance(p, n);
  };
  return options;
}

}  // namespace

CombinedSolution::CombinedSolution(const RadiosityOptions& radiosity, const DmOptions& dm)
    : direct_(dm), indirect_(withExactDirect(radiosity, direct_)) {}

void CombinedSolution::build(const DynamicScene& scene) {
  direct_.build(scene);
  indirect_.build(scene);
}

void CombinedSolution::update(const DynamicScene& scene, const SceneChange& change) {
  direct_.update(scene, change);
  indirect_.update(scene, change);
}

std::optional<CombinedSample> CombinedSolution::sample(const Vec3& p, const Vec3& n) const {
  const std::optional<Rgb> direct = direct_.irradiance(p, n);
  if (!direct) return std::nullopt;
  const std::optional<RadiositySample> radiosity = indirect_.sample(p, n);
  return CombinedSample{*direct, radiosity ? radiosity->indirect : Rgb{}};
}

IrradianceMesh CombinedSolution::displayMesh(double maxEdgeLength) const {
  IrradianceMesh mesh = buildIrradianceMesh(direct_, maxEdgeLength);
  const PosedScene& posed = direct_.posedScene();
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3& normal = posed.polygons[mesh.receiverOf[v]].plane.normal;
    if (const std::optional<RadiositySample> s = indirect_.sample(mesh.positions[v], normal))
      mesh.irradiance[v] += s->indirect;
  }
  return mesh;
}

}  // namespace penumbra
