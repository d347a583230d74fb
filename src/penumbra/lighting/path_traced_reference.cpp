#include "penumbra/lighting/path_traced_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "penumbra/base/split_mix.h"
#include "penumbra/geometry/cosine_direction.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/spatial/ray_caster.h"

namespace penumbra {

PathTracedReference::PathTracedReference(const PosedScene& scene, const RayCaster& caster,
                                         const ExactReference& reference)
    : scene_(scene), caster_(caster), reference_(reference) {}

PathTracedEstimate PathTracedReference::irradiance(const Vec3& point, const Vec3& normal,
                                                   PolygonId receiver, int paths,
                                                   std::uint64_t seed) const {
  PathTracedEstimate estimate;
  const Vec3 n0 = normalize(normal);
  estimate.direct = reference_.irradiance(point, n0, receiver);
  SplitMix rng(seed);
  Rgb sum, sumOfSquares;
  const int count = std::max(1, paths);
  for (int path = 0; path < count; ++path) {
    Rgb throughput = Rgb::gray(1), value;
    Vec3 x = point, n = n0;
    PolygonId from = receiver;
    for (;;) {
      // Drawn azimuth first, then radius (in sequence: function arguments are not).
      const double azimuth = rng.uniform(), radius = rng.uniform();
      const Vec3 d = cosineDirection(n, radius, azimuth);
      ++estimate.rays;
      const auto hit =
          caster_.intersect(x, d, caster_.epsilon(), std::numeric_limits<double>::infinity(), from);
      if (!hit) break;
      const WorldPolygon& met = scene_.polygons[hit->polygon];
      if (dot(met.plane.normal, d) >= 0) break;  // its back: nothing comes from there
      const Rgb rho = scene_.materialOf(met).reflectance;
      throughput = throughput * rho;
      if (!(throughput.maxComponent() > 0)) break;
      value += throughput * reference_.irradiance(hit->point, met.plane.normal, met.id);
      // Russian roulette: go on with the probability of the largest reflectance met here.
      const double survival = std::min(0.95, rho.maxComponent());
      if (!(rng.uniform() < survival)) break;
      throughput = throughput / survival;
      x = hit->point;
      n = met.plane.normal;
      from = met.id;
    }
    sum += value;
    sumOfSquares += value * value;
  }
  estimate.indirect = sum / double(count);
  const Rgb variance = sumOfSquares / double(count) - estimate.indirect * estimate.indirect;
  estimate.indirectStandardError =
      Rgb{std::sqrt(std::max(0.0, variance.r)), std::sqrt(std::max(0.0, variance.g)),
          std::sqrt(std::max(0.0, variance.b))} /
      std::sqrt(double(count));
  return estimate;
}

}  // namespace penumbra
