// Form factors. Between two elements the transfer is the receiver-area mean of the exact
// point-to-polygon form factor (Lambert's formula on the source clipped to the receiver point's
// front half-space) at the centroids of the receiver's four children: exact per point, so the
// sum over the sources seen from a point is 1 in a closed scene up to visibility. When a cluster
// is involved the transfer is a Monte Carlo estimate over area-uniform point pairs of
// cos⁺ cos⁺ / (π r² + A_s / N) (the disk regularisation keeps it bounded), with each pair's ray
// giving the visibility, so form factor and visibility use the same pairs.

#include "penumbra/radiosity/radiosity_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>
#include <unordered_map>

#include "penumbra/base/check.h"
#include "penumbra/geometry/triangulation.h"
#include "penumbra/lighting/form_factor.h"
#include "penumbra/spatial/ray_caster.h"
#include "penumbra/spatial/receiver_locator.h"
#include "penumbra/spatial/uniform_grid.h"

namespace penumbra {

namespace {

// SplitMix64 (Steele, Lea & Flood 2014): a tiny seeded generator; one per link keeps the
// estimates independent of the order links are refined in.
class SplitMix {
 public:
  explicit SplitMix(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t state_;
};

std::uint64_t linkSeed(std::uint64_t seed, NodeRef r, NodeRef s) {
  SplitMix mix(seed ^ (std::uint64_t(r.index) << 1 | r.kind) * 0x100000001b3ull ^
               (std::uint64_t(s.index) << 33 | std::uint64_t(s.kind) << 32));
  mix.next();
  return mix.next();
}

Polygon3 loopOf(const Element& e) {
  return Polygon3(e.vertices.begin(), e.vertices.begin() + e.vertexCount);
}

// Form factor from the point x (normal n) to the front side of element s.
double pointToElement(const Vec3& x, const Vec3& n, const Element& s) {
  if (dot(s.normal, x - s.vertices[0]) <= 0) return 0;  // x behind the source: it emits forward
  const Polygon3 clipped = clipByPlane(loopOf(s), Plane::fromPointNormal(x, n));
  if (clipped.size() < 3) return 0;
  return std::max(0.0, pointToPolygonFormFactor(x, n, clipped));
}

}  // namespace

void RadiositySolver::estimate(Link& link) {
  SplitMix rng(linkSeed(options_.seed, link.receiver, link.source));
  const NodeRef r = link.receiver, s = link.source;
  if (!r.isCluster() && !s.isCluster()) {
    const Element& re = elements_[r.index];
    const Element& se = elements_[s.index];
    // Midpoint rule on the receiver's grandchildren: 16 points, enough for pairs that share an
    // edge, where the point form factor has a logarithmic profile.
    double transfer = 0, lowest = 1e300, highest = 0;
    for (const auto& loop : re.childVertices()) {
      Element child;
      child.vertices = loop;
      child.vertexCount = re.vertexCount;
      for (const auto& subLoop : child.childVertices()) {
        const double a = elementArea(subLoop, re.vertexCount);
        Vec3 c{0, 0, 0};
        for (int i = 0; i < re.vertexCount; ++i) c += subLoop[i];
        c = c / double(re.vertexCount);
        const double f = pointToElement(c, re.normal, se);
        transfer += a * f;
        lowest = std::min(lowest, f);
        highest = std::max(highest, f);
      }
    }
    link.unoccludedTransfer = float(transfer / re.area);
    link.transferSpread = float(highest - lowest);
    if (link.unoccludedTransfer <= 0) {
      link.visibility = 0;
      return;
    }
    // Stratified jittered points on both ends, the source strata shuffled against the receiver's.
    const int n = std::max(1, options_.visibilityRays);
    const int side = std::max(1, int(std::lround(std::sqrt(double(n)))));
    std::vector<int> order(n);
    for (int i = 0; i < n; ++i) order[i] = i;
    for (int i = n - 1; i > 0; --i) std::swap(order[i], order[rng.next() % (i + 1)]);
    int unoccluded = 0;
    for (int i = 0; i < n; ++i) {
      const auto stratum = [&](int k, double& u, double& v) {
        const int cell = k % (side * side);
        u = (cell % side + rng.uniform()) / side;
        v = (cell / side + rng.uniform()) / side;
      };
      double u, v;
      stratum(i, u, v);
      const Vec3 x = re.samplePoint(u, v);
      stratum(order[i], u, v);
      const Vec3 y = se.samplePoint(u, v);
      if (!rays_->isOccluded(x, y)) ++unoccluded;
    }
    stats_.visibilityRays += n;
    link.visibility = float(double(unoccluded) / n);
    return;
  }
  // A cluster at one end or both: point pairs, each with its kernel and its ray.
  const int n = std::max(1, options_.clusterSamples);
  const double sourceArea = area(s);
  double unoccluded = 0, visible = 0;
  for (int i = 0; i < n; ++i) {
    const SurfacePoint x = samplePoint(r, rng.uniform(), rng.uniform(), (i + rng.uniform()) / n);
    const SurfacePoint y = samplePoint(s, rng.uniform(), rng.uniform(), rng.uniform());
    const Vec3 d = y.position - x.position;
    const double r2 = dot(d, d);
    if (r2 == 0) continue;
    const double cx = dot(x.normal, d), cy = -dot(y.normal, d);
    if (cx <= 0 || cy <= 0) continue;
    const double kernel = cx * cy / r2 / (std::numbers::pi * r2 + sourceArea / n);
    unoccluded += kernel;
    ++stats_.visibilityRays;
    if (!rays_->isOccluded(x.position, y.position)) visible += kernel;
  }
  link.unoccludedTransfer = float(sourceArea * unoccluded / n);
  link.transferSpread = link.unoccludedTransfer;
  link.visibility = unoccluded > 0 ? float(visible / unoccluded) : 0.f;
}

}  // namespace penumbra
