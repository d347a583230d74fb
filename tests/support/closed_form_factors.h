#pragma once
// Form factors with closed forms, for checking solvers against (Howell's catalogue of radiation
// configuration factors).

#include <cmath>
#include <numbers>

namespace penumbra::test {

// Howell's catalogue (C-11): parallel, directly opposed rectangles a x b at distance c.
inline double parallelRectangles(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double x1 = std::sqrt(1 + x * x), y1 = std::sqrt(1 + y * y);
  return 2 / (std::numbers::pi * x * y) *
         (std::log(std::sqrt((1 + x * x) * (1 + y * y) / (1 + x * x + y * y))) +
          x * y1 * std::atan(x / y1) + y * x1 * std::atan(y / x1) - x * std::atan(x) -
          y * std::atan(y));
}
// Howell (C-14): perpendicular rectangles with a common edge of length l, widths w (receiver)
// and h (source); H = h / l, W = w / l. Form factor from the receiver to the source.
inline double perpendicularRectangles(double l, double w, double h) {
  const double H = h / l, W = w / l;
  const double a = (1 + W * W) * (1 + H * H) / (1 + W * W + H * H);
  const double b = W * W * (1 + W * W + H * H) / ((1 + W * W) * (W * W + H * H));
  const double c = H * H * (1 + H * H + W * W) / ((1 + H * H) * (H * H + W * W));
  return 1 / (std::numbers::pi * W) *
         (W * std::atan(1 / W) + H * std::atan(1 / H) -
          std::sqrt(H * H + W * W) * std::atan(1 / std::sqrt(H * H + W * W)) +
          0.25 * std::log(a * std::pow(b, W * W) * std::pow(c, H * H)));
}

}  // namespace penumbra::test
