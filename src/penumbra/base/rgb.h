#pragma once
// Radiometric RGB triple (irradiance, exitance, radiance or reflectance per channel).

#include <cmath>

namespace penumbra {

struct Rgb {
  double r = 0, g = 0, b = 0;

  constexpr Rgb() = default;
  constexpr Rgb(double red, double green, double blue) : r(red), g(green), b(blue) {}
  static constexpr Rgb gray(double v) { return {v, v, v}; }

  constexpr Rgb operator+(const Rgb& o) const { return {r + o.r, g + o.g, b + o.b}; }
  constexpr Rgb operator-(const Rgb& o) const { return {r - o.r, g - o.g, b - o.b}; }
  constexpr Rgb operator*(const Rgb& o) const { return {r * o.r, g * o.g, b * o.b}; }
  constexpr Rgb operator*(double s) const { return {r * s, g * s, b * s}; }
  constexpr Rgb operator/(double s) const { return {r / s, g / s, b / s}; }
  constexpr Rgb& operator+=(const Rgb& o) { return *this = *this + o; }
  constexpr bool operator==(const Rgb&) const = default;

  constexpr bool isBlack() const { return r == 0 && g == 0 && b == 0; }
  constexpr double maxComponent() const { return r > g ? (r > b ? r : b) : (g > b ? g : b); }
  constexpr double average() const { return (r + g + b) / 3; }
  bool isFinite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
};

constexpr Rgb operator*(double s, const Rgb& c) {
  return c * s;
}

}  // namespace penumbra
