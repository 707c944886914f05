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

// A service runs until it is stopped: the candidates stay bounded (a thumbnail a second was 0.75 GB
// an hour), and the sheet still spans the whole run.
TEST(ContactSheetSink, ALongRunKeepsBoundedCandidatesSpreadToItsEnd) {
  const auto path = std::filesystem::temp_directory_path() / "fieldcast_contact_sheet_long" / "sheet.png";
  std::filesystem::remove_all(path.parent_path());
  ContactSheetSink sheet({path, 4, 2, 32, 1});
  sheet.open(StreamFormat{});
  constexpr std::uint64_t kFields = 20'000;
  std::size_t most = 0;
  for (std::uint64_t k = 0; k < kFields; ++k) {
    const Field f = greyField(k, static_cast<std::uint8_t>(16 + k / 100));  // brighter as the run goes on
    if (!sheet.wants(f)) continue;
    ASSERT_EQ(sheet.consume(f), SinkStatus::Ok);
    most = std::max(most, sheet.candidates());
  }
  EXPECT_LT(most, static_cast<std::size_t>(kCandidatesPerThumbnail) * 4);
  EXPECT_GE(sheet.candidates(), static_cast<std::size_t>(kCandidatesPerThumbnail) * 4 / 2 - 1);
  EXPECT_GE(sheet.everyNth(), 512u);  // thinned from 1 as the run went on
  sheet.close();
  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<unsigned char> rgb(static_cast<std::size_t>(spec.width) * spec.height * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, rgb.data()));
  auto green = [&](int x, int y) { return rgb[(static_cast<std::size_t>(y) * spec.width + x) * 3 + 1]; };
  // The first picture is field 0 (luma 16: dark); the last one from the run's last tenth (luma
  // 196 or more; the sheet's RGB a little brighter than video-range luma)
  EXPECT_LT(green(4 + 28, 4 + 20), 40);
  EXPECT_GT(green(4 + 32 + 4 + 28, 4 + 24 + 4 + 20), 190);
  std::filesystem::remove_all(path.parent_path());
}

// The hub asks before it queues a field: the first (the sheet's zero time), then only those on
// the grid.
TEST(ContactSheetSink, WantsTheFirstFieldThenOnlyThoseOnItsGrid) {
  const auto path = std::filesystem::temp_directory_path() / "fieldcast_contact_sheet_wants" / "sheet.png";
  ContactSheetSink sheet({path, 4, 2, 32, 10});
  EXPECT_TRUE(sheet.wants(greyField(7, 50)));  // nothing consumed yet: the run's first field
  ASSERT_EQ(sheet.consume(greyField(7, 50)), SinkStatus::Ok);
  std::vector<std::uint64_t> wanted;
  for (std::uint64_t k = 8; k < 35; ++k) {
    if (sheet.wants(greyField(k, 50))) wanted.push_back(k);
  }
  EXPECT_EQ(wanted, (std::vector<std::uint64_t>{10, 20, 30}));
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
