#include "penumbra/render/tone_mapping.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

double srgbEncode(double linear) {
  if (!(linear > 0)) return 0;  // also NaN
  if (linear >= 1) return 1;
  if (linear <= 0.0031308) return 12.92 * linear;
  return 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
}

std::uint8_t srgb8(double linear) {
  return static_cast<std::uint8_t>(std::lround(255 * srgbEncode(linear)));
}

std::vector<std::uint8_t> toSrgb8(const Image& image, const ToneMapping& toneMapping) {
  std::vector<std::uint8_t> bytes;
  bytes.reserve(image.pixels.size() * 3);
  for (const Rgb& c : image.pixels) {
    bytes.push_back(srgb8(c.r * toneMapping.exposure));
    bytes.push_back(srgb8(c.g * toneMapping.exposure));
    bytes.push_back(srgb8(c.b * toneMapping.exposure));
  }
  return bytes;
}

double luminance(const Rgb& c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

double autoExposure(const Image& image) {
  std::vector<double> values;
  values.reserve(image.pixels.size());
  for (const Rgb& c : image.pixels) {
    const double y = luminance(c);
    if (y > 0 && std::isfinite(y)) values.push_back(y);
  }
  if (values.empty()) return 1;
  const auto rank = static_cast<std::ptrdiff_t>(0.99 * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), values.begin() + rank, values.end());
  return 0.9 / values[static_cast<std::size_t>(rank)];
}

}  // namespace penumbra
