#include "penumbra/render/exr_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <stdexcept>

namespace penumbra {
namespace {

std::filesystem::path outputDirectory() {
  const std::filesystem::path dir =
      std::filesystem::path(PENUMBRA_BINARY_DIR) / "test_output" / "render";
  std::filesystem::create_directories(dir);
  return dir;
}

float f(double v) {
  return static_cast<float>(v);
}

TEST(ExrIo, RoundTripIsExactForFloatValues) {
  // Random floats over many magnitudes. (Not f(0.1 * x) in a loop: GCC 12.2 at -O2 vectorises
  // (double)(float)(c * i) as a double induction and drops the rounding to float.)
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> mantissa(0, 1);
  std::uniform_int_distribution<int> exponent(-30, 30);
  auto value = [&] { return std::ldexp(mantissa(rng), exponent(rng)); };
  Image image(9, 4);
  for (Rgb& c : image.pixels) c = {value(), value(), value()};
  image.at(0, 0) = {0, -1.5, f(3.14159)};  // negative radiance survives too
  const std::filesystem::path path = outputDirectory() / "round_trip.exr";
  writeExr(image, path);
  const Image read = readExr(path);
  ASSERT_EQ(read.width, image.width);
  ASSERT_EQ(read.height, image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) EXPECT_EQ(read.at(x, y), image.at(x, y)) << x << y;
}

TEST(ExrIo, DoublesAreRoundedToFloat) {
  const Image image(1, 1, Rgb(0.1, 0.2, 0.3));
  const std::filesystem::path path = outputDirectory() / "rounded.exr";
  writeExr(image, path);
  EXPECT_EQ(readExr(path).at(0, 0), Rgb(f(0.1), f(0.2), f(0.3)));
}

TEST(ExrIo, ErrorsNameThePath) {
  const std::filesystem::path missing = outputDirectory() / "no_such_directory" / "x.exr";
  try {
    writeExr(Image(2, 2), missing);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  try {
    readExr(missing);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra
