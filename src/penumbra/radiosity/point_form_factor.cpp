#include "penumbra/radiosity/point_form_factor.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace penumbra {

double pointToElementFormFactor(const Vec3& x, const Vec3& n, const ElementShape& s) {
  if (dot(s.normal, x - s.vertices[0]) <= 0) return 0;  // x behind the source: it emits forward
  std::array<double, 4> side{};
  bool allInFront = true, allBehind = true;
  for (int i = 0; i < s.vertexCount; ++i) {
    side[i] = dot(n, s.vertices[i] - x);
    allInFront = allInFront && side[i] >= 0;
    allBehind = allBehind && side[i] <= 0;
  }
  if (allBehind) return 0;
  std::array<Vec3, 5> loop{};
  int count = 0;
  if (allInFront) {
    for (int i = 0; i < s.vertexCount; ++i) loop[count++] = s.vertices[i] - x;
  } else {
    for (int i = 0; i < s.vertexCount; ++i) {
      const int j = (i + 1) % s.vertexCount;
      if (side[i] >= 0) loop[count++] = s.vertices[i] - x;
      if ((side[i] > 0 && side[j] < 0) || (side[i] < 0 && side[j] > 0)) {
        const double t = side[i] / (side[i] - side[j]);
        loop[count++] = s.vertices[i] + (s.vertices[j] - s.vertices[i]) * t - x;
      }
    }
    if (count < 3) return 0;
  }
  double sum = 0;
  for (int i = 0; i < count; ++i) {
    const Vec3& a = loop[i];
    const Vec3& b = loop[(i + 1) % count];
    const Vec3 c = cross(b, a);
    const double sinTimesLengths = length(c);
    if (sinTimesLengths == 0) continue;
    sum += std::atan2(sinTimesLengths, dot(a, b)) * dot(n, c) / sinTimesLengths;
  }
  return std::max(0.0, sum / (2 * std::numbers::pi));
}

}  // namespace penumbra
