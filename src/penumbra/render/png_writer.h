#pragma once
// 8-bit sRGB PNG output of a radiometric image (tone-mapped with tone_mapping.h).

#include <cstdint>
#include <filesystem>
#include <vector>

#include "penumbra/render/image.h"
#include "penumbra/render/tone_mapping.h"

namespace penumbra {

// Writes toSrgb8(image, toneMapping) as an RGB PNG, row 0 at the top.
// Throws std::runtime_error naming `path` when the image is empty or the file cannot be written.
void writePng(const Image& image, const ToneMapping& toneMapping,
              const std::filesystem::path& path);

// Writes display values as they are (interleaved 8-bit RGB, row 0 at the top): screenshots of
// what a window shows. Throws std::runtime_error naming `path` when the size is empty or does not
// match rgb.size() == width * height * 3, or the file cannot be written.
void writePngRgb8(const std::vector<std::uint8_t>& rgb, int width, int height,
                  const std::filesystem::path& path);

}  // namespace penumbra
