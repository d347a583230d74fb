#pragma once
// OpenEXR files for radiometric images (irradiance maps, rendered radiance): unclamped
// 32-bit float R, G, B channels, losslessly (ZIP) compressed.

#include <filesystem>

#include "penumbra/render/image.h"

namespace penumbra {

// Writes `image` with each channel rounded to float (values that are floats survive exactly;
// negative, huge and NaN values are stored as they are). Throws std::runtime_error naming `path`
// when the file cannot be written.
void writeExr(const Image& image, const std::filesystem::path& path);

// Reads the R, G, B channels of the data window (a missing channel reads as 0) into an Image with
// row 0 at the top of the data window. Throws std::runtime_error naming `path` on failure.
Image readExr(const std::filesystem::path& path);

}  // namespace penumbra
