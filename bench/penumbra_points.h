#pragma once
// Penumbra points for the benchmarks that compare against Monte Carlo: random receiver points
// whose exact irradiance lies strictly between 5% and 95% of the unoccluded value (red channel).

#include <cstdint>
#include <vector>

#include "penumbra/lighting/exact_reference.h"
#include "penumbra/scene/receiver_sampling.h"

namespace penumbra::bench {

struct PenumbraPoint {
  ReceiverPoint point;
  double exact = 0;  // the reference irradiance there (red channel)
};

// Up to `count` such points among 20,000 random receiver points drawn with `seed`.
inline std::vector<PenumbraPoint> samplePenumbraPoints(const PosedScene& scene,
                                                       const ExactReference& reference,
                                                       size_t count, std::uint64_t seed) {
  std::vector<PenumbraPoint> out;
  for (const ReceiverPoint& q : sampleReceiverPoints(scene, 20000, seed)) {
    const double e = reference.irradiance(q.p, q.n, q.receiver).r;
    double unoccluded = 0;
    for (PolygonId light : scene.lights)
      unoccluded += reference.unoccludedFormFactor(q.p, q.n, light) *
                    scene.materialOf(scene.polygons[light]).emission.r;
    if (e > 0.05 * unoccluded && e < 0.95 * unoccluded) out.push_back({q, e});
    if (out.size() == count) break;
  }
  return out;
}

}  // namespace penumbra::bench
