#pragma once
// Monte Carlo estimate of the direct irradiance of DESIGN.md §5, independent of the exact engines:
//   E(p) = sum over lights of M * (1/pi) * integral over the light of
//          cos(theta_p) cos(theta_y) / r^2 * V(p, y) dA_y,
// with cos(theta_p) = max(0, n . w) (w the unit direction from p to y), only the light's front side
// emitting (cos(theta_y) > 0 on its front, else 0), and V from RayCaster::isOccluded: every polygon
// occludes, other lights included, except those whose plane holds p or y (the receiver, the light).
// The estimate comes with its standard error, from independent replicate batches.

#include <cstdint>
#include <vector>

#include "penumbra/base/rgb.h"
#include "penumbra/scene/posed_scene.h"
#include "penumbra/spatial/ray_caster.h"

namespace penumbra {

struct MonteCarloOptions {
  // Samples of each light in each batch, split over the light's triangles in proportion to area;
  // every triangle gets at least one, so a light with more triangles than this uses one each.
  int samplesPerLightPerBatch = 256;
  // Independent replicates; the standard error needs at least 2.
  int batches = 16;
  std::uint64_t seed = 1;
};

struct MonteCarloEstimate {
  Rgb mean;            // average of the batch estimates (W/m^2)
  Rgb standardError;   // sample std of the batch estimates / sqrt(batches); NaN if batches == 1
  long long rays = 0;  // shadow rays cast (samples rejected by the cosines cast none)
};

class MonteCarloEstimator {
 public:
  // Keeps a reference to `caster`, which must outlive this estimator and have been built from the
  // same scene; copies what it needs of the lights (their triangulation) from `scene`.
  MonteCarloEstimator(const PosedScene& scene, const RayCaster& caster);

  // Direct irradiance at `point` for a receiver with front normal `normal` (any non-zero length).
  // Stratified: each batch maps a jittered grid of strata of the unit square onto every light
  // triangle (area-preserving square-root map), so each batch is an unbiased estimate on its own.
  // Deterministic: the random stream is seeded from options.seed and a hash of (point, normal), so
  // the result does not depend on the order of calls or on the thread. Thread-safe.
  // Throws std::invalid_argument if samplesPerLightPerBatch < 1 or batches < 1.
  MonteCarloEstimate irradiance(const Vec3& point, const Vec3& normal,
                                const MonteCarloOptions& options = {}) const;

 private:
  struct Triangle {
    Vec3 a, b, c;
    double area = 0;
  };
  struct Light {
    PolygonId polygon = 0;
    Rgb exitance;
    Plane plane;
    double area = 0;
    std::vector<Triangle> triangles;
  };

  const RayCaster& caster_;
  std::vector<Light> lights_;
};

}  // namespace penumbra
