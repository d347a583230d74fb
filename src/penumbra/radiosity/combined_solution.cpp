#include "penumbra/radiosity/combined_solution.h"

#include <bit>
#include <cstdint>

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

CombinedSolution::CombinedSolution(const RadiosityOptions& radiosity, const DmOptions& dm,
                                   int indirectRays)
    : direct_(dm), indirect_(withExactDirect(radiosity, direct_)), indirectRays_(indirectRays) {}

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
  // The seed from the point's coordinates: the same point gets the same answer, whatever the
  // order or the thread it is asked in.
  std::uint64_t seed = 0x9e3779b97f4a7c15ull;
  for (double c : {p.x, p.y, p.z})
    seed = (seed ^ std::bit_cast<std::uint64_t>(c)) * 0x100000001b3ull;
  const std::optional<Rgb> indirect = indirect_.gatheredIndirect(p, n, indirectRays_, seed);
  return CombinedSample{*direct, indirect ? *indirect : Rgb{}};
}

IrradianceMesh CombinedSolution::displayMesh(double maxEdgeLength) const {
  IrradianceMesh mesh = buildIrradianceMesh(direct_, maxEdgeLength);
  const PosedScene& posed = direct_.posedScene();
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3& normal = posed.polygons[mesh.receiverOf[v]].plane.normal;
    if (const std::optional<RadiositySample> s = indirect_.sample(mesh.positions[v], normal))
      mesh.irradiance[v] += s->indirect;  // interpolated: a gather per corner costs too much
  }
  return mesh;
}

}  // namespace penumbra
