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
  const std::vector<std::uint8_t> bytes = toSrgb8(image, toneMapping);
  const int stride = image.width * 3;
  if (stbi_write_png(path.c_str(), image.width, image.height, 3, bytes.data(), stride) == 0) {
    throw std::runtime_error("cannot write PNG '" + path.string() + "'");
  }
}

}  // namespace penumbra
