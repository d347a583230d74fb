#pragma once
// A radiometric image: linear RGB values (radiance, or irradiance for irradiance maps) per pixel,
// row 0 at the top as in every image file format. Tone mapping to display values is separate
// (tone_mapping.h), so images can be compared and stored without loss.

#include <vector>

#include "penumbra/base/check.h"
#include "penumbra/base/rgb.h"

namespace penumbra {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<Rgb> pixels;  // row-major, pixels[y * width + x], y = 0 is the top row

  Image() = default;
  // Precondition: width >= 0, height >= 0. Every pixel is `fill`.
  Image(int w, int h, const Rgb& fill = {});

  // Precondition: 0 <= x < width, 0 <= y < height (checked in debug builds).
  Rgb& at(int x, int y) {
    DCHECK(x >= 0 && x < width && y >= 0 && y < height);
    return pixels[static_cast<std::size_t>(y) * width + x];
  }
  const Rgb& at(int x, int y) const {
    DCHECK(x >= 0 && x < width && y >= 0 && y < height);
    return pixels[static_cast<std::size_t>(y) * width + x];
  }
  bool empty() const { return pixels.empty(); }
};

}  // namespace penumbra
