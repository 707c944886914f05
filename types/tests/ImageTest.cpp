#include <fieldcast/Image.h>

#include <gtest/gtest.h>

namespace fieldcast {
namespace {

TEST(Image, RowsAreTightlyPacked) {
  Image img(5, 3, PixelFormat::Rgb8);
  EXPECT_EQ(img.strideBytes(), 15u);
  EXPECT_EQ(img.bytes().size(), 45u);
  EXPECT_EQ(img.row(2) - img.row(0), 30);
  img.row(1)[4] = 200;
  EXPECT_EQ(img.bytes()[19], 200);
}

TEST(Image, FormatsHaveTheirRowSizes) {
  EXPECT_EQ(rowBytes(PixelFormat::Grey8, 720), 720u);
  EXPECT_EQ(rowBytes(PixelFormat::Rgb8, 720), 2160u);
  EXPECT_EQ(rowBytes(PixelFormat::Uyvy422, 720), 1440u);
}

TEST(Image, RejectsBadShapes) {
  EXPECT_THROW(Image(-1, 4, PixelFormat::Grey8), std::invalid_argument);
  EXPECT_THROW(Image(719, 4, PixelFormat::Uyvy422), std::invalid_argument);
}

TEST(Image, ResizeReshapesAndZeroes) {
  Image img(4, 4, PixelFormat::Grey8);
  img.row(0)[0] = 9;
  img.resize(2, 2, PixelFormat::Uyvy422);
  EXPECT_EQ(img.widthPx(), 2);
  EXPECT_EQ(img.format(), PixelFormat::Uyvy422);
  EXPECT_EQ(img.bytes().size(), 8u);
  EXPECT_EQ(img.bytes()[0], 0);
}

}  // namespace
}  // namespace fieldcast
