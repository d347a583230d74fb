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

// Adversarial points on `receiver`: where the line from each light vertex through each vertex of
// the other polygons meets it (the corners of EV events, where mesh faces meet), each also moved
// by `step` to either side along two directions of the receiver's plane; only points inside the
// receiver polygon, on its front side seen from the light vertex.
std::vector<ReceiverPoint> vertexShadowPoints(const PosedScene& scene, PolygonId receiver,
                                              double step);

}  // namespace penumbra
