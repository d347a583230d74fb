#include "penumbra/render/png_writer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

// The test's own PNG reader (stb_image); STATIC keeps it from clashing with libstb.so.
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#include <stb_image.h>

namespace penumbra {
namespace {

std::filesystem::path outputDirectory() {
  const std::filesystem::path dir =
      std::filesystem::path(PENUMBRA_BINARY_DIR) / "test_output" / "render";
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(PngWriter, WrittenBytesReadBackAsTheToneMappedImage) {
  // Odd width: rows of 3 * 7 bytes are not 4-byte aligned.
  Image image(7, 5);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      image.at(x, y) = {x / 6.0, y / 4.0, (x + y) % 3 == 0 ? 5.0 : 0.01 * x};
  const ToneMapping toneMapping{.exposure = 0.8};
  const std::filesystem::path path = outputDirectory() / "png_round_trip.png";
  writePng(image, toneMapping, path);

  int width = 0, height = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &width, &height, &channels, 3);
  ASSERT_NE(data, nullptr) << stbi_failure_reason();
  const std::vector<std::uint8_t> read(data, data + width * height * 3);
  stbi_image_free(data);
  EXPECT_EQ(width, 7);
  EXPECT_EQ(height, 5);
  EXPECT_EQ(channels, 3);
  EXPECT_EQ(read, toSrgb8(image, toneMapping));
  // Row 0 is the top row of the file: pixel (0, 0) has green 0, the last row green 1 * exposure.
  EXPECT_EQ(read[1], 0);
  EXPECT_EQ(read[(4 * 7) * 3 + 1], srgb8(0.8));
}

TEST(PngWriter, UnwritablePathThrowsNamingIt) {
  const Image image(2, 2, Rgb::gray(0.5));
  const std::filesystem::path path = outputDirectory() / "no_such_directory" / "x.png";
  try {
    writePng(image, {}, path);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra
