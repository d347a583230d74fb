#include "penumbra/lighting/form_factor.h"

#include <cmath>
#include <numbers>

namespace penumbra {

double pointToPolygonFormFactor(const Vec3& p, const Vec3& n, const Polygon3& loop) {
  double sum = 0;
  const size_t count = loop.size();
  for (size_t i = 0; i < count; ++i) {
    const Vec3 a = loop[i] - p;
    const Vec3 b = loop[(i + 1) % count] - p;
    const Vec3 c = cross(b, a);
    const double sinTimesLengths = length(c);
    if (sinTimesLengths == 0) continue;  // edge through p's line of sight: subtends no angle
    // atan2 of (|a×b|, a·b) is accurate for both tiny and near-π angles, unlike acos.
    const double gamma = std::atan2(sinTimesLengths, dot(a, b));
    sum += gamma * dot(n, c) / sinTimesLengths;
  }
  return sum / (2 * std::numbers::pi);
}

}  // namespace penumbra
