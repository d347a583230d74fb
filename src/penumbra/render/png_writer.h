#pragma once
// 8-bit sRGB PNG output of a radiometric image (tone-mapped with tone_mapping.h).

#include <filesystem>

#include "penumbra/render/image.h"
#include "penumbra/render/tone_mapping.h"

namespace penumbra {

// Writes toSrgb8(image, toneMapping) as an RGB PNG, row 0 at the top.
// Throws std::runtime_error naming `path` when the image is empty or the file cannot be written.
void writePng(const Image& image, const ToneMapping& toneMapping,
              const std::filesystem::path& path);

}  // namespace penumbra
