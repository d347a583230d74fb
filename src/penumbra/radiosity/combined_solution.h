#pragma once
// Exact direct light with radiosity's indirect light: one solution, accurate at every point.
//
// The direct irradiance comes from the discontinuity mesh (exact: each face's backprojection),
// the indirect from hierarchical radiosity whose final solution takes every leaf's direct
// irradiance from that mesh (RadiosityOptions::exactDirect), so the light the surfaces reflect
// starts from the exact first bounce. At a point: E = E_direct(DM, exact at the point) +
// E_indirect(the radiosity solution gathered at the point: RadiositySolver::gatheredIndirect,
// exact form factors and visibility to the wholly visible sources, rays for the rest; a ray that
// meets a leaf closer than the leaf's size takes what the point it met reflects, its exact direct
// light and a path on), so nothing is interpolated and no light leaks under furniture or through
// a gap from a leaf reaching into the light. Both engines share one live scene.
//
// Measured against the independent path tracer (bench/radiosity_error_curve --combined
// --points 250, 1e-3, 1,024 rays per point; docs/radiosity.md, session 23): median 0.68%, p95
// 4.2% in the Cornell box (radiosity alone: 3.7% and 23%), 0.33% and 1.4% in the chair room, 0.53%
// and 4.5% in the furnished room, 0.28% and 1.4% in desk-145; the indirect part summed over the
// points within 0.7% of the path tracer's. Rays take the radiosity of the leaf's cell they meet
// (not the leaf's mean, which had the indirect light 1-2% low).

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
  // `radiosity.exactDirect` is replaced by the discontinuity mesh's; `indirectRays` rays per
  // point share what the exact sources leave of its hemisphere.
  explicit CombinedSolution(const RadiosityOptions& radiosity = {}, const DmOptions& dm = {},
                            int indirectRays = 1024);
  CombinedSolution(const CombinedSolution&) = delete;
  CombinedSolution& operator=(const CombinedSolution&) = delete;

  // Builds both parts at the scene's current pose (the scene must outlive their use of it).
  void build(const DynamicScene& scene);
  // After `change` was applied to the scene: the direct part by the discontinuity mesh's
  // incremental update, the indirect part by the radiosity solver's update (a full solve until
  // the line-space update lands).
  void update(const DynamicScene& scene, const SceneChange& change);

  // Direct and indirect irradiance at p (unit normal n) on a receiver facing n; nothing when p
  // lies on no receiver. Deterministic for a point (the rays' seed comes from its coordinates).
  // Not thread-safe: the discontinuity mesh's exact arrangements cache lazily.
  std::optional<CombinedSample> sample(const Vec3& p, const Vec3& n) const;

  // For display: the discontinuity mesh's faces triangulated (buildIrradianceMesh: exact direct
  // irradiance at every corner, triangles no longer than maxEdgeLength), each corner's
  // irradiance the total, with radiosity's indirect part interpolated there (not gathered as
  // sample() does: a gather per corner, about 1 ms, would take minutes for a room).
  IrradianceMesh displayMesh(double maxEdgeLength) const;

  const DiscontinuityMeshEngine& direct() const { return direct_; }
  const RadiositySolver& indirect() const { return indirect_; }

 private:
  DiscontinuityMeshEngine direct_;
  RadiositySolver indirect_;
  int indirectRays_ = 1024;
};

}  // namespace penumbra
