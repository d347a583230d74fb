#pragma once
// Exact direct light with radiosity's indirect light: one solution, accurate at every point.
//
// The direct irradiance comes from the discontinuity mesh (exact: each face's backprojection),
// the indirect from hierarchical radiosity whose final solution takes every leaf's direct
// irradiance from that mesh (RadiosityOptions::exactDirect), so the light the surfaces reflect
// starts from the exact first bounce. At a point: E = E_direct(DM, exact at the point) +
// E_indirect(radiosity, interpolated over its leaves). Both engines share one live scene.

#include <optional>

#include "penumbra/base/rgb.h"
#include "penumbra/dm/discontinuity_mesh_engine.h"
#include "penumbra/dm/irradiance_mesh.h"
#include "penumbra/radiosity/radiosity_solver.h"

namespace penumbra {

class DynamicScene;
struct SceneChange;

struct CombinedSample {
  Rgb direct;    // exact (the discontinuity mesh)
  Rgb indirect;  // radiosity's, lit by the exact direct light
  Rgb total() const { return direct + indirect; }
};

class CombinedSolution {
 public:
  // `radiosity.exactDirect` is replaced by the discontinuity mesh's.
  explicit CombinedSolution(const RadiosityOptions& radiosity = {}, const DmOptions& dm = {});
  CombinedSolution(const CombinedSolution&) = delete;
  CombinedSolution& operator=(const CombinedSolution&) = delete;

  // Builds both parts at the scene's current pose (the scene must outlive their use of it).
  void build(const DynamicScene& scene);
  // After `change` was applied to the scene: the direct part by the discontinuity mesh's
  // incremental update, the indirect part by the radiosity solver's update (a full solve until
  // the line-space update lands).
  void update(const DynamicScene& scene, const SceneChange& change);

  // Direct and indirect irradiance at p (unit normal n) on a receiver facing n; nothing when p
  // lies on no receiver.
  std::optional<CombinedSample> sample(const Vec3& p, const Vec3& n) const;

  // For display: the discontinuity mesh's faces triangulated (buildIrradianceMesh: exact direct
  // irradiance at every corner, triangles no longer than maxEdgeLength), each corner's
  // irradiance the total, with radiosity's indirect part interpolated there.
  IrradianceMesh displayMesh(double maxEdgeLength) const;

  const DiscontinuityMeshEngine& direct() const { return direct_; }
  const RadiositySolver& indirect() const { return indirect_; }

 private:
  DiscontinuityMeshEngine direct_;
  RadiositySolver indirect_;
};

}  // namespace penumbra
