#include "penumbra/geometry/spherical_triangle.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace penumbra {

std::optional<Vec3> sampleSphericalTriangle(const Vec3& x, const Vec3& a, const Vec3& b,
                                            const Vec3& c, double u1, double u2,
                                            double* solidAngle) {
  const Vec3 A = normalize(a - x), B = normalize(b - x), C = normalize(c - x);
  const Vec3 nab = cross(A, B), nac = cross(A, C), nbc = cross(B, C);
  if (length(nab) < 1e-12 || length(nac) < 1e-12 || length(nbc) < 1e-12) return std::nullopt;
  const auto angle = [](const Vec3& p, const Vec3& q) {
    return std::acos(std::clamp(dot(normalize(p), normalize(q)), -1.0, 1.0));
  };
  const double alpha = angle(nab, nac), beta = angle(-nab, nbc), gamma = angle(-nac, -nbc);
  const double area = alpha + beta + gamma - std::numbers::pi;
  if (solidAngle) *solidAngle = area;
  if (!(area > 1e-12)) return std::nullopt;
  const double cosC = dot(A, B);
  const double areaHat = u1 * area;
  const double s = std::sin(areaHat - alpha), t = std::cos(areaHat - alpha);
  const double uu = t - std::cos(alpha), vv = s + std::sin(alpha) * cosC;
  const double q =
      std::clamp(((vv * t - uu * s) * std::cos(alpha) - vv) / ((vv * s + uu * t) * std::sin(alpha)),
                 -1.0, 1.0);
  const Vec3 cPerp = C - A * dot(C, A);
  if (length(cPerp) < 1e-12) return std::nullopt;
  const Vec3 cHat = A * q + normalize(cPerp) * std::sqrt(std::max(0.0, 1 - q * q));
  const double z = 1 - u2 * (1 - dot(cHat, B));
  const Vec3 hPerp = cHat - B * dot(cHat, B);
  if (length(hPerp) < 1e-12) return B;
  return normalize(B * z + normalize(hPerp) * std::sqrt(std::max(0.0, 1 - z * z)));
}

}  // namespace penumbra
