#include "penumbra/dm/discontinuity_surface.h"

#include <algorithm>

namespace penumbra {

Vec3 CriticalFan::normal() const {
  // Any two independent directions of the fan: S0→H0 and the moving one.
  const Vec3 along = hinge0 - source0;
  const Vec3 moving = (hinge1 - hinge0) + (source1 - source0);
  return normalize(cross(moving, along));
}

double CriticalFan::criticalParameter(const Vec3& x) const {
  // x lies on L(u) iff n · ((H(u) − S(u)) × (x − S(u))) = 0. With one of S, H fixed, the quadratic
  // term is a cross product of a vector with itself, so the equation is linear in u: f(u) = f0 + u
  // k.
  const Vec3 n = normal();
  const auto f = [&](double u) {
    const Vec3 s = source(u);
    return dot(n, cross(hinge(u) - s, x - s));
  };
  const double f0 = f(0), f1 = f(1);
  return f0 / (f0 - f1);
}

double CriticalFan::depthParameter(const Vec3& x, double u) const {
  const Vec3 s = source(u);
  const Vec3 d = hinge(u) - s;
  return dot(x - s, d) / dot(d, d);
}

double CriticalFan::hingeDepth(double u) const {
  double depth = 1;
  if (contacts.empty()) return depth;
  // L(u) = S + s (H − S) meets the contact C0 + t (C1 − C0) in the fan's plane.
  const Vec3 n = normal();
  const Vec3 s0 = source(u), d = hinge(u) - s0;
  for (const auto& [c0, c1] : contacts) {
    const Vec3 e = c1 - c0;
    const double denominator = dot(n, cross(d, e));
    if (denominator == 0) continue;
    const double s = dot(n, cross(c0 - s0, e)) / denominator;
    const double t = dot(n, cross(c0 - s0, d)) / denominator;
    // A contact the line misses by rounding at its ends still counts: the relative slack only
    // lengthens the stretch where nothing may block.
    if (t >= -1e-9 && t <= 1 + 1e-9) depth = std::max(depth, s);
  }
  return depth;
}

}  // namespace penumbra
