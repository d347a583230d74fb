#pragma once
// Display of radiometric images: exposure, then the sRGB transfer function, then 8-bit rounding.
// Kept on the CPU and separate from rendering so that rendered images stay radiometric (EXR,
// comparisons) and every engine's picture is tone-mapped the same way.

#include <cstdint>
#include <vector>

#include "penumbra/render/image.h"

namespace penumbra {

struct ToneMapping {
  double exposure = 1;  // display value = sRGB(clamp(radiance * exposure, 0, 1))
};

// The sRGB OETF (IEC 61966-2-1): 12.92 v below 0.0031308, else 1.055 v^(1/2.4) - 0.055.
// Input is clamped to [0, 1] first; NaN maps to 0 so one bad pixel cannot poison a picture.
double srgbEncode(double linear);

// round(255 * srgbEncode(linear)).
std::uint8_t srgb8(double linear);

// Interleaved 8-bit RGB, row 0 at the top, size width * height * 3.
std::vector<std::uint8_t> toSrgb8(const Image& image, const ToneMapping& toneMapping);

// Rec. 709 luminance of linear RGB.
double luminance(const Rgb& c);

// An exposure that maps the 99th percentile of the luminances of the non-black pixels to 0.9, so
// a few hot pixels (a light seen directly) clip while the rest of the picture keeps its range.
// Black pixels (background, umbra) are left out so that the result does not depend on how much of
// the frame is empty. Returns 1 when no pixel has positive luminance.
double autoExposure(const Image& image);

}  // namespace penumbra
