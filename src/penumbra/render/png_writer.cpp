#include "penumbra/render/png_writer.h"

#include <stdexcept>

// The one translation unit that compiles stb_image_write. STATIC keeps its functions local, so
// they cannot clash with (or be interposed by) the copies in Debian's libstb.so.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb_image_write.h>

namespace penumbra {

void writePng(const Image& image, const ToneMapping& toneMapping,
              const std::filesystem::path& path) {
  if (image.width <= 0 || image.height <= 0) {
    throw std::runtime_error("cannot write PNG '" + path.string() + "': the image is empty");
  }
  writePngRgb8(toSrgb8(image, toneMapping), image.width, image.height, path);
}

void writePngRgb8(const std::vector<std::uint8_t>& rgb, int width, int height,
                  const std::filesystem::path& path) {
  if (width <= 0 || height <= 0 || rgb.size() != std::size_t(width) * std::size_t(height) * 3) {
    throw std::runtime_error("cannot write PNG '" + path.string() +
                             "': empty image or pixel data of the wrong size");
  }
  if (stbi_write_png(path.c_str(), width, height, 3, rgb.data(), width * 3) == 0) {
    throw std::runtime_error("cannot write PNG '" + path.string() + "'");
  }
}

}  // namespace penumbra
