#include <io_bridge/ContactSheetSink.h>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>

namespace fieldcast::io {
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

TEST(ContactSheetSink, SpreadsThumbnailsOverTheRunAndWritesAPngAtClose) {
  const auto path = std::filesystem::temp_directory_path() / "fieldcast_contact_sheet_test" / "sheet.png";
  std::filesystem::remove_all(path.parent_path());
  ContactSheetSink sheet({path, 4, 2, 32, 10});
  sheet.open(StreamFormat{});  // creates the folder
  for (std::uint64_t k = 0; k < 100; ++k) {
    ASSERT_EQ(sheet.consume(greyField(k, static_cast<std::uint8_t>(16 + 2 * k))), SinkStatus::Ok);
  }
  EXPECT_EQ(sheet.candidates(), 10u);
  sheet.close();
  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec& spec = in->spec();
  // 2 columns of 32 px + gaps; interlaced 64×24 fields shown at raster aspect: 32×24 thumbnails.
  ASSERT_EQ(spec.width, 2 * 32 + 3 * 4);
  ASSERT_EQ(spec.height, 2 * 24 + 3 * 4);
  ASSERT_EQ(spec.nchannels, 3);
  std::vector<unsigned char> rgb(static_cast<std::size_t>(spec.width) * spec.height * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, rgb.data()));
  auto green = [&](int x, int y) { return rgb[(static_cast<std::size_t>(y) * spec.width + x) * 3 + 1]; };
  // The last thumbnail (field 90) is brighter than the first (field 0): the sheet goes forward in time.
  EXPECT_LT(green(4 + 28, 4 + 20) + 100, green(4 + 32 + 4 + 28, 4 + 24 + 4 + 20));
  std::filesystem::remove_all(path.parent_path());
}

TEST(ContactSheetSink, EmptySheetIsAnErrorNamingThePathAndCloseWritesNothing) {
  ContactSheetSink sheet({"/tmp/never.png"});
  sheet.close();
  EXPECT_FALSE(std::filesystem::exists("/tmp/never.png"));
  try {
    sheet.write();
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/tmp/never.png"), std::string::npos);
  }
}

}  // namespace
}  // namespace fieldcast::io
