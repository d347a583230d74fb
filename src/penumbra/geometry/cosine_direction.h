#pragma once
// Cosine-distributed directions (Malley's method): a point uniform on the unit disc lifted to the
// hemisphere has density cos θ / π, the weight of a direction in irradiance, so the mean over
// such directions of the radiosity met is the irradiance.

#include <algorithm>
#include <cmath>
#include <numbers>

#include "penumbra/geometry/vec3.h"

namespace penumbra {

// A direction about the unit normal n from two numbers in [0, 1): u1 the squared radius on the
// disc (1 − cos² θ), u2 the azimuth as a fraction of a turn.
inline Vec3 cosineDirection(const Vec3& n, double u1, double u2) {
  const Vec3 t = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 u = normalize(cross(n, t)), v = cross(n, u);
  const double r = std::sqrt(u1), phi = 2 * std::numbers::pi * u2;
  return u * (r * std::cos(phi)) + v * (r * std::sin(phi)) + n * std::sqrt(std::max(0.0, 1 - u1));
}

}  // namespace penumbra
