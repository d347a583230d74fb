#include "penumbra/render/png_writer.h"

#include <stdexcept>

#include "penumbra/base/output_file.h"

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
  int size = 0;
  unsigned char* png = stbi_write_png_to_mem(rgb.data(), width * 3, width, height, 3, &size);
  if (!png) throw std::runtime_error("cannot write PNG '" + path.string() + "': encoding failed");
  try {
    writeOutputFile(
        path, [&](std::ostream& out) { out.write(reinterpret_cast<const char*>(png), size); });
  } catch (...) {
    STBIW_FREE(png);
    throw;
  }
  STBIW_FREE(png);
}

}  // namespace penumbra
