// Mirrored fields (a rear-view mirror, a rear-projection screen): the same picture as the plain
// field, its columns and/or raster lines reversed, for every scan and at run time.
#include "AnalyticScene.h"

#include <prp_warp/FieldWarper.h>

#include <gtest/gtest.h>

#include <cstring>

namespace fieldcast::warp {
namespace {

constexpr int kW = 160, kH = 120;  // test::obliqueFrame()'s display window

const Frame& scene() { return test::obliqueFrame(); }

// The field of `parity` of the scene, warped to the frame's own pose, mirrored so.
Image fieldOf(FieldParity parity, Mirror mirror, int rasterHeightPx = kH) {
  FieldWarperConfig cfg;
  cfg.rasterWidthPx = kW;
  cfg.rasterHeightPx = rasterHeightPx;
  cfg.outputFormat = PixelFormat::Rgb8;
  cfg.mirror = mirror;
  FieldWarper warper(cfg);
  Field field = warper.makeField();
  EXPECT_EQ(warper.produce(scene(), scene().pose, FieldSpec{0, TimePoint{}, parity}, field), FieldStatus::Ok);
  return field.image;
}

const std::uint8_t* pixel(const Image& image, int x, int y) { return image.row(y) + 3 * x; }

bool samePixel(const Image& a, int ax, int ay, const Image& b, int bx, int by) {
  return std::memcmp(pixel(a, ax, ay), pixel(b, bx, by), 3) == 0;
}

// The plain picture must be neither left-right nor top-bottom symmetric (terrain below sky), or
// the comparisons below would hold for a mirror that did nothing.
TEST(FieldMirror, ThePlainPictureIsNotSymmetric) {
  const Image plain = fieldOf(FieldParity::Progressive, Mirror::None);
  int leftRight = 0, topBottom = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      leftRight += !samePixel(plain, x, y, plain, kW - 1 - x, y);
      topBottom += !samePixel(plain, x, y, plain, x, kH - 1 - y);
    }
  }
  EXPECT_GT(leftRight, kW * kH / 4);
  EXPECT_GT(topBottom, kW * kH / 2);
}

TEST(FieldMirror, HorizontalReversesEachLine) {
  for (FieldParity parity : {FieldParity::Top, FieldParity::Bottom, FieldParity::Progressive}) {
    const Image plain = fieldOf(parity, Mirror::None);
    const Image mirrored = fieldOf(parity, Mirror::Horizontal);
    int differ = 0;
    for (int y = 0; y < plain.heightPx(); ++y) {
      for (int x = 0; x < kW; ++x) differ += !samePixel(mirrored, x, y, plain, kW - 1 - x, y);
    }
    EXPECT_EQ(differ, 0) << static_cast<int>(parity);
  }
}

// Mirrored top to bottom, raster line y shows line H−1−y. On an even raster that line belongs to
// the other field, so each interlaced field is the other field's lines in reverse order.
TEST(FieldMirror, VerticalReversesTheRasterLinesAcrossTheFields) {
  for (int rasterHeight : {kH, kH - 1}) {
    const Image progressive = fieldOf(FieldParity::Progressive, Mirror::None, rasterHeight);
    for (FieldParity parity : {FieldParity::Top, FieldParity::Bottom}) {
      const Image mirrored = fieldOf(parity, Mirror::Vertical, rasterHeight);
      const int first = parity == FieldParity::Top ? 0 : 1;
      int differ = 0;
      for (int i = 0; i < mirrored.heightPx(); ++i) {
        const int line = first + 2 * i;  // this field's raster line
        for (int x = 0; x < kW; ++x) differ += !samePixel(mirrored, x, i, progressive, x, rasterHeight - 1 - line);
      }
      EXPECT_EQ(differ, 0) << "raster " << rasterHeight << ", parity " << static_cast<int>(parity);
    }
  }
}

TEST(FieldMirror, BothIsAHalfTurnAndSetMirrorTakesEffectAtTheNextField) {
  const Image plain = fieldOf(FieldParity::Progressive, Mirror::None);
  FieldWarperConfig cfg;
  cfg.rasterWidthPx = kW;
  cfg.rasterHeightPx = kH;
  cfg.outputFormat = PixelFormat::Rgb8;
  FieldWarper warper(cfg);
  Field field = warper.makeField();
  const FieldSpec spec{0, TimePoint{}, FieldParity::Progressive};
  ASSERT_EQ(warper.produce(scene(), scene().pose, spec, field), FieldStatus::Ok);
  EXPECT_TRUE(samePixel(field.image, 10, 10, plain, 10, 10));
  warper.setMirror(Mirror::Both);
  ASSERT_EQ(warper.produce(scene(), scene().pose, spec, field), FieldStatus::Ok);
  int differ = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) differ += !samePixel(field.image, x, y, plain, kW - 1 - x, kH - 1 - y);
  }
  EXPECT_EQ(differ, 0);
}

TEST(FieldMirror, GreyImagesOfOddSizeMirrorInPlace) {
  Image grey(3, 3, PixelFormat::Grey8);
  for (int i = 0; i < 9; ++i) grey.bytes()[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i);
  mirrorInPlace(grey, Mirror::Horizontal);
  EXPECT_EQ(std::vector<std::uint8_t>(grey.bytes().begin(), grey.bytes().end()),
            (std::vector<std::uint8_t>{2, 1, 0, 5, 4, 3, 8, 7, 6}));
  mirrorInPlace(grey, Mirror::Vertical);
  EXPECT_EQ(std::vector<std::uint8_t>(grey.bytes().begin(), grey.bytes().end()),
            (std::vector<std::uint8_t>{8, 7, 6, 5, 4, 3, 2, 1, 0}));
}

}  // namespace
}  // namespace fieldcast::warp
