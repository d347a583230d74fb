#pragma once
// The structure-aware target's scenes: small, valid-by-construction scenes whose geometry comes
// from the fuzzer's decisions (fuzz_input.h), aimed at the configurations exact soft shadows find
// hard (DESIGN.md §7): an area light above a floor and 1 to kMaxOccluders occluder polygons of up
// to kMaxCorners corners, with
// - repeated corners (consecutive, and a loop closed by repeating its first corner), corners on
//   an edge's line (collinear edges) and corners nudged by 1e-15 to 1e-9 of the polygon's size;
// - tiny and huge magnitudes: polygons from 1e-9 to 3 units across, the whole scene scaled by
//   1e-6 to 1e6 and moved up to 1e6 away from the origin, baked into the corners or given as the
//   objects' transform;
// - coplanar polygons (an occluder in another's plane, lying on the floor, in the light's plane),
//   touching ones (an occluder resting on the floor by a corner or an edge, two sharing an edge)
//   and occluders aligned with the light's corners and edges;
// - optionally a second keyframe that moves the last occluder (an incremental update).
// The polygons are planar and simple by construction in exact arithmetic only: validateScene
// still decides (and rejects what rounding or the nudges broke).

#include <vector>

#include "fuzz_input.h"
#include "penumbra/scene/scene.h"

namespace penumbra::fuzz {

// The objects, in order: the light, the floor, the occluders (one polygon each).
inline constexpr int kLightObject = 0;
inline constexpr int kFloorObject = 1;
inline constexpr int kFirstOccluderObject = 2;
inline constexpr int kMaxOccluders = 3;
// Enough for every shape of the configurations above; a bound keeps each input fast (the number
// of discontinuity surfaces grows with the product of edge counts).
inline constexpr int kMaxCorners = 8;
// Before scaling: the floor is [-kFloorHalfSize, kFloorHalfSize]^2 at z = 0 facing +z, the light
// faces -z at z = kLightHeight.
inline constexpr double kFloorHalfSize = 3;
inline constexpr double kLightHeight = 2;

struct FuzzedScene {
  Scene scene;
  // Points strictly inside the floor, in the floor object's coordinates (posed by its transform).
  std::vector<Vec3> floorPoints;
  // The last occluder has a second keyframe: the scene has frames 0 and 1.
  bool moves = false;
};

FuzzedScene makeFuzzedScene(FuzzInput& in);

}  // namespace penumbra::fuzz
