#include "penumbra/lighting/path_traced_reference.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "penumbra/base/split_mix.h"
#include "penumbra/geometry/cosine_direction.h"
#include "penumbra/geometry/spherical_triangle.h"
#include "penumbra/lighting/exact_reference.h"
#include "penumbra/spatial/ray_caster.h"

namespace penumbra {

PathTracedReference::PathTracedReference(const PosedScene& scene, const RayCaster& caster,
                                         const ExactReference& reference)
    : scene_(scene), caster_(caster), reference_(&reference) {}

PathTracedReference::PathTracedReference(const PosedScene& scene, const RayCaster& caster)
    : scene_(scene), caster_(caster) {
  double total = 0;
  for (const WorldPolygon& p : scene_.polygons) {
    const double power = scene_.materialOf(p).emission.maxComponent() * area(p.vertices);
    if (!(power > 0)) continue;
    emitters_.push_back(p.id);
    cumulativePower_.push_back(total += power);
  }
}

Rgb PathTracedReference::direct(const Vec3& y, const Vec3& n, PolygonId on, SplitMix& rng) const {
  if (reference_) return reference_->irradiance(y, n, on);
  if (emitters_.empty()) return {};
  // An emitter drawn in proportion to its power.
  const double total = cumulativePower_.back();
  const double pick = rng.uniform() * total;
  const size_t k =
      std::min<size_t>(std::upper_bound(cumulativePower_.begin(), cumulativePower_.end(), pick) -
                           cumulativePower_.begin(),
                       emitters_.size() - 1);
  const WorldPolygon& light = scene_.polygons[emitters_[k]];
  if (light.id == on || !(light.plane.signedDistance(y) > 0)) return {};  // y behind it: dark
  const double probability = (cumulativePower_[k] - (k > 0 ? cumulativePower_[k - 1] : 0)) / total;
  // A direction uniform in the solid angle the light subtends at y (Arvo 1995, per triangle of
  // its fan, drawn by solid angle): E = ∫ (M / π) cos θ_y V dω ≈ M Ω cos θ_y V / (π p(emitter)).
  // Bounded weights (radiance M / π), unlike points uniform in area, whose 1/r² has a heavy tail
  // next to an edge the light shares with the receiver (the furnace's floor beside a wall).
  const std::vector<Vec3>& v = light.vertices;
  std::array<double, 16> omega{};
  const size_t triangles = std::min(v.size() - 2, omega.size());
  double solidAngle = 0;
  for (size_t t = 0; t < triangles; ++t) {
    sampleSphericalTriangle(y, v[0], v[t + 1], v[t + 2], 0, 0, &omega[t]);
    if (!(omega[t] > 0) || !std::isfinite(omega[t])) omega[t] = 0;
    solidAngle += omega[t];
  }
  double pick2 = rng.uniform() * solidAngle;
  const double u1 = rng.uniform(), u2 = rng.uniform();
  if (!(solidAngle > 0)) return {};
  size_t t = 0;
  while (t + 1 < triangles && pick2 >= omega[t]) pick2 -= omega[t++];
  const auto d = sampleSphericalTriangle(y, v[0], v[t + 1], v[t + 2], u1, u2);
  if (!d) return {};
  const double cosY = dot(n, *d), towards = dot(light.plane.normal, *d);
  if (cosY <= 0 || towards >= 0) return {};
  const Vec3 q = y + *d * (light.plane.signedDistance(y) / -towards);
  if (caster_.isOccluded(y, q)) return {};
  return scene_.materialOf(light).emission * (solidAngle * cosY / (std::numbers::pi * probability));
}

PathTracedEstimate PathTracedReference::irradiance(const Vec3& point, const Vec3& normal,
                                                   PolygonId receiver, int paths,
                                                   std::uint64_t seed) const {
  PathTracedEstimate estimate;
  const Vec3 n0 = normalize(normal);
  SplitMix rng(seed);
  if (reference_) estimate.direct = reference_->irradiance(point, n0, receiver);
  Rgb sum, sumOfSquares, directSum, directSquares, totalSquares;
  const int count = std::max(1, paths);
  for (int path = 0; path < count; ++path) {
    const Rgb first = reference_ ? estimate.direct : direct(point, n0, receiver, rng);
    directSum += first;
    directSquares += first * first;
    Rgb throughput = Rgb::gray(1), value;
    Vec3 x = point, n = n0;
    PolygonId from = receiver;
    for (;;) {
      // Drawn azimuth first, then radius (in sequence: function arguments are not).
      const double azimuth = rng.uniform(), radius = rng.uniform();
      const Vec3 d = cosineDirection(n, radius, azimuth);
      ++estimate.rays;
      // The side of a two-sided card facing the ray, not whichever the caster returns: taking
      // its back, a path ended there (the cards of a generated room read as half black).
      const auto hit = firstSurfaceSeen(caster_, scene_, x, d, caster_.epsilon(),
                                        std::numeric_limits<double>::infinity(), from);
      if (!hit) break;
      const WorldPolygon& met = scene_.polygons[hit->polygon];
      if (dot(met.plane.normal, d) >= 0) break;  // its back: nothing comes from there
      const Rgb rho = scene_.materialOf(met).reflectance;
      throughput = throughput * rho;
      if (!(throughput.maxComponent() > 0)) break;
      value += throughput * direct(hit->point, met.plane.normal, met.id, rng);
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
    totalSquares += (first + value) * (first + value);
  }
  const auto standardError = [count](const Rgb& mean, const Rgb& meanOfSquares) {
    const Rgb variance = meanOfSquares - mean * mean;
    return Rgb{std::sqrt(std::max(0.0, variance.r)), std::sqrt(std::max(0.0, variance.g)),
               std::sqrt(std::max(0.0, variance.b))} /
           std::sqrt(double(count));
  };
  estimate.indirect = sum / double(count);
  estimate.indirectStandardError = standardError(estimate.indirect, sumOfSquares / double(count));
  if (!reference_) {
    estimate.direct = directSum / double(count);
    estimate.directStandardError = standardError(estimate.direct, directSquares / double(count));
  }
  estimate.totalStandardError =
      standardError(estimate.direct + estimate.indirect, totalSquares / double(count));
  return estimate;
}

}  // namespace penumbra
