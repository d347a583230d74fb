// Monte Carlo direct irradiance with stratified area sampling and replicate batches.
// References:
//  - M. F. Cohen, J. R. Wallace, "Radiosity and Realistic Image Synthesis", 1993, §4.9 (area
//    sampling of the point-to-polygon form factor with shadow rays).
//  - G. Turk, "Generating Random Points in Triangles", Graphics Gems I, 1990; M. Pharr, W. Jakob,
//    G. Humphreys, "Physically Based Rendering", §A.5 / §13.6 (the area-preserving square-root map
//    from the unit square to a triangle; stratified jittered sampling).
//  - A. B. Owen, "Monte Carlo Theory, Methods and Examples", 2013, ch. 8 (stratification: each
//    stratum weighted by its measure is unbiased) and ch. 2 (replicates for the standard error of
//    estimators whose samples are not independent, like stratified ones).
//  - D. Blackman, S. Vigna, "Scrambled Linear Pseudorandom Number Generators", ACM TOMS 47(4),
//    2021 (xoshiro256++, seeded by SplitMix64).

#include "penumbra/lighting/monte_carlo_estimator.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "penumbra/geometry/polygon.h"
#include "penumbra/geometry/triangulation.h"

namespace penumbra {

namespace {

std::uint64_t splitMix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// xoshiro256++: small, fast, and its output is fixed by its definition (unlike std::
// distributions), so estimates are reproducible across standard libraries.
class Random {
 public:
  explicit Random(std::uint64_t seed) {
    for (auto& word : state_) word = splitMix64(seed);
  }
  // Uniform in [0, 1).
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t next() {
    const std::uint64_t result = std::rotl(state_[0] + state_[3], 23) + state_[0];
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = std::rotl(state_[3], 45);
    return result;
  }
  std::uint64_t state_[4];
};

std::uint64_t hashQuery(std::uint64_t seed, const Vec3& point, const Vec3& normal) {
  std::uint64_t state = seed;
  std::uint64_t hash = splitMix64(state);
  for (double value : {point.x, point.y, point.z, normal.x, normal.y, normal.z}) {
    state ^= std::bit_cast<std::uint64_t>(value) + hash;
    hash = splitMix64(state);
  }
  return hash;
}

// Samples per triangle: proportional to area (largest remainder), at least one each so that no
// part of the light goes unsampled (which would bias the estimate).
std::vector<int> allocateSamples(const std::vector<double>& areas, double total, int samples) {
  const int n = int(areas.size());
  std::vector<int> counts(n);
  std::vector<std::pair<double, int>> remainders(n);
  int given = 0;
  for (int i = 0; i < n; ++i) {
    const double share = samples * areas[i] / total;
    counts[i] = int(std::floor(share));
    remainders[i] = {share - counts[i], i};
    given += counts[i];
  }
  std::sort(remainders.begin(), remainders.end(), [](const auto& x, const auto& y) {
    return x.first > y.first || (x.first == y.first && x.second < y.second);
  });
  for (int k = 0; given < samples && k < n; ++k, ++given) ++counts[remainders[k].second];
  for (int& c : counts) c = std::max(c, 1);
  return counts;
}

}  // namespace

MonteCarloEstimator::MonteCarloEstimator(const PosedScene& scene, const RayCaster& caster)
    : caster_(caster) {
  for (PolygonId id : scene.lights) {
    const WorldPolygon& polygon = scene.polygons[id];
    Light light;
    light.polygon = id;
    light.exitance = scene.materialOf(polygon).emission;
    light.plane = polygon.plane;
    for (const auto& t : triangulate(polygon.vertices)) {
      Triangle triangle{polygon.vertices[t[0]], polygon.vertices[t[1]], polygon.vertices[t[2]]};
      triangle.area = triangleArea(triangle.a, triangle.b, triangle.c);
      light.area += triangle.area;
      light.triangles.push_back(triangle);
    }
    if (light.triangles.empty() || light.exitance.isBlack()) continue;  // emits nothing
    lights_.push_back(std::move(light));
  }
}

MonteCarloEstimate MonteCarloEstimator::irradiance(const Vec3& point, const Vec3& normal,
                                                   const MonteCarloOptions& options) const {
  if (options.samplesPerLightPerBatch < 1)
    throw std::invalid_argument("Monte Carlo: samplesPerLightPerBatch must be at least 1");
  if (options.batches < 1) throw std::invalid_argument("Monte Carlo: batches must be at least 1");
  const Vec3 n = normalize(normal);
  Random random(hashQuery(options.seed, point, n));

  // The sample layout depends only on the options and the light, not on the batch.
  std::vector<std::vector<int>> counts;
  counts.reserve(lights_.size());
  for (const Light& light : lights_) {
    std::vector<double> areas;
    for (const Triangle& t : light.triangles) areas.push_back(t.area);
    counts.push_back(allocateSamples(areas, light.area, options.samplesPerLightPerBatch));
  }

  MonteCarloEstimate estimate;
  std::vector<Rgb> batchValues;
  batchValues.reserve(options.batches);
  for (int batch = 0; batch < options.batches; ++batch) {
    Rgb value;
    for (size_t l = 0; l < lights_.size(); ++l) {
      const Light& light = lights_[l];
      // Only the front side emits: from behind the light's plane (or in it) nothing arrives.
      if (!(light.plane.signedDistance(point) > 0)) continue;
      double integral = 0;  // of cos cos / (pi r^2) V over the light
      for (size_t k = 0; k < light.triangles.size(); ++k) {
        const Triangle& tri = light.triangles[k];
        // Rows x columns strata of the unit square, columns varying by at most one between rows;
        // each stratum is weighted by its own area, so any sample count is unbiased.
        const int samples = counts[l][k];
        const int rows = std::max(1, int(std::lround(std::sqrt(double(samples)))));
        double sum = 0;
        for (int row = 0; row < rows; ++row) {
          const int columns = samples / rows + (row < samples % rows ? 1 : 0);
          const double weight = 1.0 / (double(rows) * columns);
          for (int column = 0; column < columns; ++column) {
            const double u1 = (row + random.uniform()) / rows;
            const double u2 = (column + random.uniform()) / columns;
            const double s = std::sqrt(u1);
            const Vec3 y = tri.a * (1 - s) + tri.b * (s * (1 - u2)) + tri.c * (s * u2);
            const Vec3 d = y - point;
            const double r2 = squaredLength(d);
            if (!(r2 > 0)) continue;
            const double cosP = dot(n, d);                    // times r
            const double cosY = -dot(light.plane.normal, d);  // times r
            if (cosP <= 0 || cosY <= 0) continue;
            ++estimate.rays;
            if (caster_.isOccluded(point, y)) continue;
            sum += weight * cosP * cosY / (r2 * r2);
          }
        }
        integral += tri.area * sum;
      }
      value += light.exitance * (integral / std::numbers::pi);
    }
    batchValues.push_back(value);
  }

  const double b = options.batches;
  for (const Rgb& v : batchValues) estimate.mean += v;
  estimate.mean = estimate.mean / b;
  if (options.batches < 2) {
    const double unknown = std::numeric_limits<double>::quiet_NaN();
    estimate.standardError = {unknown, unknown, unknown};
    return estimate;
  }
  Rgb squares;
  for (const Rgb& v : batchValues) {
    const Rgb e = v - estimate.mean;
    squares += e * e;
  }
  const Rgb variance = squares / (b - 1);
  estimate.standardError = {std::sqrt(variance.r / b), std::sqrt(variance.g / b),
                            std::sqrt(variance.b / b)};
  return estimate;
}

}  // namespace penumbra
