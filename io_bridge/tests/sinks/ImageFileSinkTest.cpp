#include <io_bridge/ImageFileSink.h>

#include "PixelConvert.h"
#include "TestFields.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <unistd.h>

#include <cmath>
#include <limits>

namespace fieldcast::io {
namespace {

using testing::makeField;
using testing::testFormat;
namespace fs = std::filesystem;

fs::path scratchDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("fieldcast_images_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(ImageFileSink, WritesEveryNthFieldAsPng) {
  const fs::path dir = scratchDir("png");
  const StreamFormat f = testFormat(64, 16);
  ImageFileSink sink({dir, 2, ImageFileFormat::Png, "field"});
  sink.open(f);
  for (std::uint64_t k = 0; k < 5; ++k) ASSERT_EQ(sink.consume(makeField(f, k)), SinkStatus::Ok);
  EXPECT_EQ(sink.filesWritten(), 3u);  // 0, 2, 4
  const fs::path path = dir / "field_00000004_bottom.png";
  ASSERT_TRUE(fs::exists(path)) << path;
  EXPECT_TRUE(fs::exists(dir / "field_00000000_bottom.png"));

  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec& spec = in->spec();
  EXPECT_EQ(spec.width, 64);
  EXPECT_EQ(spec.height, 8);
  EXPECT_EQ(spec.nchannels, 3);
  EXPECT_NEAR(spec.get_float_attribute("PixelAspectRatio"), 1.0f / 2.0f, 1e-6);  // field of square pixels
  std::vector<std::uint8_t> pixels(64 * 8 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data()));
  const Field field = makeField(f, 4);
  std::vector<std::uint8_t> expected(64 * 3);
  for (int r = 0; r < 8; ++r) {
    rowToRgb(field.image.row(r), field.image.format(), 64, expected.data());
    ASSERT_TRUE(std::equal(expected.begin(), expected.end(), pixels.begin() + r * 64 * 3)) << "row " << r;
  }
  fs::remove_all(dir);
}

// The hub asks before it queues a field: only the fields the sink writes, so the ones between
// cost no copy and a slow write cannot fill its queue with fields it would pass over.
TEST(ImageFileSink, WantsOnlyTheFieldsItWrites) {
  const fs::path dir = scratchDir("wants");
  const StreamFormat f = testFormat(64, 16);
  ImageFileSink sink({dir, 3, ImageFileFormat::Png, "field"});
  sink.open(f);
  std::vector<std::uint64_t> wanted;
  for (std::uint64_t k = 0; k < 10; ++k) {
    if (sink.wants(makeField(f, k))) wanted.push_back(k);
  }
  EXPECT_EQ(wanted, (std::vector<std::uint64_t>{0, 3, 6, 9}));
  // A snapshot asked for: the next field is wanted, and stays wanted until one is written
  sink.requestSnapshot();
  EXPECT_TRUE(sink.wants(makeField(f, 10)));
  EXPECT_TRUE(sink.wants(makeField(f, 10)));  // asking does not clear it: only a write does
  ASSERT_EQ(sink.consume(makeField(f, 10)), SinkStatus::Ok);
  EXPECT_EQ(sink.filesWritten(), 1u);
  EXPECT_FALSE(sink.wants(makeField(f, 11)));
  // A snapshot asked for just before a field on the grid: that field answers it, the next is not
  // written as well
  sink.requestSnapshot();
  ASSERT_EQ(sink.consume(makeField(f, 12)), SinkStatus::Ok);
  EXPECT_EQ(sink.filesWritten(), 2u);
  EXPECT_FALSE(sink.wants(makeField(f, 13)));
  ASSERT_EQ(sink.consume(makeField(f, 13)), SinkStatus::Ok);
  EXPECT_EQ(sink.filesWritten(), 2u);
  ImageFileSink onDemand({dir, 0, ImageFileFormat::Png, "snap"});
  onDemand.open(f);
  EXPECT_FALSE(onDemand.wants(makeField(f, 0)));  // every_nth 0: only on demand
  fs::remove_all(dir);
}

TEST(ImageFileSink, OnDemandSnapshotAsExr) {
  const fs::path dir = scratchDir("exr");
  const StreamFormat f = testFormat(32, 8, ScanMode::Progressive, PixelFormat::Rgb8);
  ImageFileSink sink({dir, 0, ImageFileFormat::Exr, "snap"});
  sink.open(f);
  sink.consume(makeField(f, 0));
  EXPECT_EQ(sink.filesWritten(), 0u);
  sink.requestSnapshot();
  sink.consume(makeField(f, 1));
  sink.consume(makeField(f, 2));
  EXPECT_EQ(sink.filesWritten(), 1u);
  ASSERT_EQ(sink.lastPath(), dir / "snap_00000001_progressive.exr");
  auto in = OIIO::ImageInput::open(sink.lastPath().string());
  ASSERT_TRUE(in);
  std::vector<float> px(32 * 8 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.data()));
  // Linear light: code 255 is 1.0, code 0 is 0, and mid grey is far below 0.5
  const Field field = makeField(f, 1);
  const std::uint8_t code = field.image.bytes()[0];
  const double c = code / 255.0;
  const double linear = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  EXPECT_NEAR(px[0], linear, 2e-3);
  fs::remove_all(dir);
}

TEST(ImageFileSink, FrameExrCarriesTheRange) {
  const fs::path dir = scratchDir("frame");
  Frame frame;
  frame.image = Image(8, 4, PixelFormat::Rgb8);
  frame.rangeM.resize(32);
  for (std::size_t i = 0; i < 32; ++i) frame.rangeM[i] = 100.0f + 12.345f * static_cast<float>(i);
  frame.rangeM[5] = std::numeric_limits<float>::infinity();  // sky
  frame.frameNumber = 77;
  writeFrameImage(frame, dir / "frame.exr");
  auto in = OIIO::ImageInput::open((dir / "frame.exr").string());
  ASSERT_TRUE(in);
  ASSERT_EQ(in->spec().nchannels, 4);
  EXPECT_EQ(in->spec().channelnames[3], "Z");
  EXPECT_EQ(in->spec().get_string_attribute("fieldcast:frameNumber"), "77");
  std::vector<float> z(32);
  ASSERT_TRUE(in->read_image(0, 0, 3, 4, OIIO::TypeDesc::FLOAT, z.data()));
  for (std::size_t i = 0; i < 32; ++i) EXPECT_EQ(z[i], frame.rangeM[i]) << i;  // full float, not half
  fs::remove_all(dir);
}

TEST(ImageFileSink, MissingFolderIsAClearError) {
  ImageFileSink sink({"/nonexistent-fields", 1, ImageFileFormat::Png, "field"});
  try {
    sink.open(testFormat(64, 16));
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-fields is not a folder"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldcast::io
