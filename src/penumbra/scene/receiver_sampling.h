#pragma once
// Random points on the receivers of a posed scene, for tests, benchmarks and `penumbra generate
// points`: uniform by area over the front sides of the non-emitting polygons, reproducible from a
// seed.

#include <cstdint>
#include <vector>

#include "penumbra/scene/posed_scene.h"

namespace penumbra {

struct ReceiverPoint {
  Vec3 p, n;  // the point and its receiver's unit normal
  PolygonId receiver = 0;
};

std::vector<ReceiverPoint> sampleReceiverPoints(const PosedScene& scene, int count,
                                                std::uint64_t seed);

}  // namespace penumbra
