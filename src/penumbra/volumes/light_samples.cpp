#include "penumbra/volumes/light_samples.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "penumbra/base/check.h"
#include "penumbra/geometry/triangulation.h"

namespace penumbra {

std::vector<Vec3> stratifiedLightSamples(const Polygon3& polygon, int n, std::uint64_t seed) {
  CHECK_GE(n, 1);
  if (n == 1) return {centroid(polygon)};
  const auto triangles = triangulate(polygon);
  CHECK(!triangles.empty());
  std::vector<double> cumulative;
  double total = 0;
  for (const auto& t : triangles) {
    total += length(cross(polygon[t[1]] - polygon[t[0]], polygon[t[2]] - polygon[t[0]])) / 2;
    cumulative.push_back(total);
  }
  const int rows = std::max(1, int(std::floor(std::sqrt(double(n)))));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(0, 1);
  std::vector<Vec3> samples;
  samples.reserve(n);
  for (int r = 0; r < rows; ++r) {
    // Spread n cells over the rows as evenly as possible: rows r get n/rows or n/rows + 1.
    const int columns = n / rows + (r < n % rows ? 1 : 0);
    for (int c = 0; c < columns; ++c) {
      const double u = (c + jitter(rng)) / columns * total;
      const double v = (r + jitter(rng)) / rows;
      const int k =
          int(std::lower_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin());
      const int i = std::min(k, int(triangles.size()) - 1);
      const double lo = i == 0 ? 0 : cumulative[i - 1];
      const double s = std::clamp((u - lo) / (cumulative[i] - lo), 0.0, 1.0);
      // sqrt(s) sweeps area linearly from vertex 0 to the opposite edge; v runs along that edge.
      const double a = std::sqrt(s);
      const auto& t = triangles[i];
      samples.push_back(polygon[t[0]] * (1 - a) + polygon[t[1]] * (a * (1 - v)) +
                        polygon[t[2]] * (a * v));
    }
  }
  return samples;
}

}  // namespace penumbra
