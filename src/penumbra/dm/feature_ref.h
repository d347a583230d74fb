#pragma once
// A scene feature named by a polygon and a corner of it: edge `corner` → `corner + 1` of the
// polygon, or its vertex `corner`. Resolved in the posed scene of the frame being evaluated, so a
// name follows a moving object (EdgeAdjacency's vertex and edge ids are numbered afresh every
// frame).

#include <compare>

#include "penumbra/scene/posed_scene.h"

namespace penumbra {

struct FeatureRef {
  PolygonId polygon = 0;
  int corner = 0;
  auto operator<=>(const FeatureRef&) const = default;
};

}  // namespace penumbra
