#pragma once
// The distance from a point to a segment (a segment of zero length is its point).

#include <algorithm>

#include "penumbra/geometry/vec3.h"

namespace penumbra {

inline double distanceToSegment(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = dot(ab, ab);
  const double t = len2 > 0 ? std::clamp(dot(x - a, ab) / len2, 0.0, 1.0) : 0.0;
  return distance(x, a + ab * t);
}

}  // namespace penumbra
