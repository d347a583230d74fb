#pragma once
// Oriented planes n . x = d with unit normal n; the positive side is the front.

#include "penumbra/geometry/vec3.h"

namespace penumbra {

struct Plane {
  Vec3 normal{0, 0, 1};
  double offset = 0;

  // Precondition: normal is not the zero vector.
  static Plane fromPointNormal(const Vec3& point, const Vec3& normal) {
    const Vec3 n = normalize(normal);
    return {n, dot(n, point)};
  }
  double signedDistance(const Vec3& p) const { return dot(normal, p) - offset; }
  Plane flipped() const { return {-normal, -offset}; }
  Vec3 project(const Vec3& p) const { return p - normal * signedDistance(p); }
};

}  // namespace penumbra
