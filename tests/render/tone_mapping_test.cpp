#include "penumbra/render/tone_mapping.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace penumbra {
namespace {

// The sRGB OETF written out independently of the library.
double referenceSrgb(double v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
}

TEST(ToneMapping, SrgbEncodeFollowsTheStandardFormula) {
  EXPECT_EQ(srgbEncode(0), 0);
  EXPECT_DOUBLE_EQ(srgbEncode(0.001), 0.01292);
  EXPECT_DOUBLE_EQ(srgbEncode(0.0031308), 12.92 * 0.0031308);  // the threshold: linear segment
  // The two segments meet (to the standard's 4 digits) at the threshold.
  EXPECT_NEAR(srgbEncode(0.0031308), 1.055 * std::pow(0.0031308, 1 / 2.4) - 0.055, 1e-7);
  EXPECT_DOUBLE_EQ(srgbEncode(0.5), 1.055 * std::pow(0.5, 1 / 2.4) - 0.055);
  EXPECT_NEAR(srgbEncode(0.5), 0.735356983, 1e-9);
  EXPECT_DOUBLE_EQ(srgbEncode(0.18), referenceSrgb(0.18));
  EXPECT_DOUBLE_EQ(srgbEncode(1), 1);
  EXPECT_EQ(srgbEncode(1.5), 1);
  EXPECT_EQ(srgbEncode(1e30), 1);
  EXPECT_EQ(srgbEncode(-0.2), 0);
  EXPECT_EQ(srgbEncode(std::numeric_limits<double>::quiet_NaN()), 0);
  EXPECT_EQ(srgbEncode(std::numeric_limits<double>::infinity()), 1);
}

TEST(ToneMapping, ToSrgb8RoundsTheEncodedValues) {
  Image image(5, 1);
  image.at(0, 0) = {0, 0.0031308, 0.5};
  image.at(1, 0) = {1, 3, -1};
  image.at(2, 0) = Rgb::gray(0.2);
  image.at(3, 0) = {0.002, 0.8, 0.04};
  image.at(4, 0) = {std::numeric_limits<double>::quiet_NaN(), 0.999, 1.0 / 255};
  const std::vector<std::uint8_t> bytes = toSrgb8(image, {});
  ASSERT_EQ(bytes.size(), 15u);
  // Hand values: 255 * 0.040449936 = 10.31, 255 * 0.735357 = 187.52.
  EXPECT_EQ(bytes[0], 0);
  EXPECT_EQ(bytes[1], 10);
  EXPECT_EQ(bytes[2], 188);
  EXPECT_EQ(bytes[3], 255);
  EXPECT_EQ(bytes[4], 255);  // > 1 clamps
  EXPECT_EQ(bytes[5], 0);    // < 0 clamps
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const Rgb& c = image.pixels[i];
    const double channels[3] = {c.r, c.g, c.b};
    for (int k = 0; k < 3; ++k) {
      double v = channels[k];
      v = std::isnan(v) ? 0 : std::min(1.0, std::max(0.0, v));
      EXPECT_EQ(bytes[3 * i + k], static_cast<int>(std::lround(255 * referenceSrgb(v))))
          << i << "," << k;
    }
  }
}

TEST(ToneMapping, ExposureScalesBeforeEncoding) {
  Image image(2, 1);
  image.at(0, 0) = Rgb::gray(0.25);
  image.at(1, 0) = Rgb::gray(0.6);
  const std::vector<std::uint8_t> bytes = toSrgb8(image, {.exposure = 2});
  EXPECT_EQ(bytes[0], 188);  // 0.25 * 2 = 0.5
  EXPECT_EQ(bytes[3], 255);  // 1.2 clamps
}

TEST(ToneMapping, AutoExposureMapsThe99thPercentileTo0point9) {
  Image uniform(10, 10, Rgb::gray(0.5));
  EXPECT_NEAR(autoExposure(uniform), 1.8, 1e-12);
  // Black pixels (background) do not count; one hot pixel in a hundred does not set exposure.
  Image scene(20, 10, Rgb{});
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 10; ++y) scene.at(x, y) = Rgb::gray(2);
  scene.at(0, 0) = Rgb::gray(1000);
  EXPECT_NEAR(autoExposure(scene), 0.45, 1e-12);
  EXPECT_EQ(autoExposure(Image(4, 4)), 1);
  EXPECT_EQ(autoExposure(Image()), 1);
}

}  // namespace
}  // namespace penumbra
