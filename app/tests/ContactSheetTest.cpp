#include "ContactSheet.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>

namespace fieldcast::app {
namespace {

Field greyField(std::uint64_t k, std::uint8_t value) {
  Field f;
  f.image = Image(64, 24, PixelFormat::Uyvy422);
  for (std::size_t b = 0; b < f.image.bytes().size(); b += 2) {
    f.image.bytes()[b] = 128;        // neutral chroma
    f.image.bytes()[b + 1] = value;  // luma
  }
  f.parity = k % 2 == 0 ? FieldParity::Bottom : FieldParity::Top;
  f.rasterHeightPx = 48;
  f.fieldNumber = k;
  f.displayTime = TimePoint{Nanoseconds{static_cast<std::int64_t>(k) * 16'683'333}};
  return f;
}

TEST(ContactSheet, SpreadsThumbnailsOverTheRunAndWritesAPng) {
  ContactSheet sheet(4, 2, 32, 10);
  for (std::uint64_t k = 0; k < 100; ++k) sheet.add(greyField(k, static_cast<std::uint8_t>(16 + 2 * k)));
  EXPECT_EQ(sheet.candidates(), 10u);
  const auto path = std::filesystem::temp_directory_path() / "fieldcast_contact_sheet_test.png";
  sheet.write(path);
  const cv::Mat png = cv::imread(path.string());
  ASSERT_FALSE(png.empty());
  // 2 columns of 32 px + gaps; interlaced 64×24 fields shown at raster aspect: 32×24 thumbnails.
  EXPECT_EQ(png.cols, 2 * 32 + 3 * 4);
  EXPECT_EQ(png.rows, 2 * 24 + 3 * 4);
  // The last thumbnail (field 90) is brighter than the first (field 0): the sheet goes forward in time.
  const auto first = png.at<cv::Vec3b>(4 + 20, 4 + 28)[1];
  const auto last = png.at<cv::Vec3b>(4 + 24 + 4 + 20, 4 + 32 + 4 + 28)[1];
  EXPECT_LT(first + 100, last);
  std::filesystem::remove(path);
}

TEST(ContactSheet, EmptySheetIsAnErrorNamingThePath) {
  ContactSheet sheet;
  try {
    sheet.write("/tmp/never.png");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/tmp/never.png"), std::string::npos);
  }
}

}  // namespace
}  // namespace fieldcast::app
