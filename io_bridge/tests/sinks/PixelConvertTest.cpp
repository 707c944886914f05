#include "PixelConvert.h"

#include <gtest/gtest.h>

#include <vector>

namespace fieldcast::io {
namespace {

TEST(PixelConvert, Bt601ReferenceColours) {
  // Rec. 601 video range: black 16/128/128, white 235/128/128, the primaries as in every table.
  auto black = rgbToYcbcr(0, 0, 0), white = rgbToYcbcr(255, 255, 255), red = rgbToYcbcr(255, 0, 0);
  EXPECT_EQ(black.y, 16);
  EXPECT_EQ(black.cb, 128);
  EXPECT_EQ(white.y, 235);
  EXPECT_EQ(white.cr, 128);
  EXPECT_EQ(red.y, 82);
  EXPECT_EQ(red.cb, 90);
  EXPECT_EQ(red.cr, 240);
}

TEST(PixelConvert, GreyMatchesRgbOfEqualComponents) {
  std::vector<std::uint8_t> grey(256), rgb(256 * 3), a(512), b(512);
  for (int i = 0; i < 256; ++i) grey[i] = rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = static_cast<std::uint8_t>(i);
  rowToUyvy(grey.data(), PixelFormat::Grey8, 256, a.data());
  rowToUyvy(rgb.data(), PixelFormat::Rgb8, 256, b.data());
  for (int i = 0; i < 512; i += 2) EXPECT_NEAR(a[i + 1], b[i + 1], 1) << i;  // luma
  for (int i = 0; i < 512; i += 2) EXPECT_EQ(a[i], 128);                     // neutral chroma
}

TEST(PixelConvert, UyvyRoundTripThroughRgbIsClose) {
  // A flat colour survives YCbCr → RGB → YCbCr within a code value.
  const int w = 8;
  std::vector<std::uint8_t> uyvy(2 * w), rgb(3 * w), back(2 * w);
  for (int i = 0; i < w / 2; ++i) {
    uyvy[4 * i] = 90;
    uyvy[4 * i + 1] = 120;
    uyvy[4 * i + 2] = 180;
    uyvy[4 * i + 3] = 120;
  }
  rowToRgb(uyvy.data(), PixelFormat::Uyvy422, w, rgb.data());
  rowToUyvy(rgb.data(), PixelFormat::Rgb8, w, back.data());
  for (int i = 0; i < 2 * w; ++i) EXPECT_NEAR(back[i], uyvy[i], 1) << i;
}

TEST(PixelConvert, OddWidthFillsTheLastPair) {
  std::vector<std::uint8_t> rgb = {255, 255, 255, 0, 0, 0, 255, 255, 255};
  std::vector<std::uint8_t> uyvy(8, 0), y(3), cb(2), cr(2);
  rowToUyvy(rgb.data(), PixelFormat::Rgb8, 3, uyvy.data());
  EXPECT_EQ(uyvy[5], 235);  // pixel 2
  EXPECT_EQ(uyvy[7], 235);  // the padding copy of pixel 2
  uyvyToPlanar(uyvy.data(), 3, y.data(), cb.data(), cr.data());
  EXPECT_EQ(y[0], 235);
  EXPECT_EQ(y[1], 16);
  EXPECT_EQ(y[2], 235);
}

}  // namespace
}  // namespace fieldcast::io
