#include <io_bridge/ShmRing.h>
#include <io_bridge/SinkHub.h>

#include "TestFields.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <atomic>
#include <cstring>
#include <thread>

namespace fieldcast::io {
namespace {

using testing::makeField;
using testing::testFormat;

std::string ringName(const std::string& what) { return "/fieldcast_test_" + std::to_string(::getpid()) + "_" + what; }

bool samePattern(const Field& f, const StreamFormat& format) {
  const Field expected = makeField(format, f.fieldNumber);
  return f.image == expected.image && f.parity == expected.parity && f.displayTime == expected.displayTime &&
         f.sourceFrameNumber == expected.sourceFrameNumber;
}

TEST(ShmRing, ReaderSeesWhatTheWriterPublished) {
  const StreamFormat format = testFormat(64, 16);
  ShmRingWriter writer(ringName("basic"), format, 4);
  ShmRingReader reader(ringName("basic"));
  EXPECT_EQ(reader.format().widthPx, 64);
  EXPECT_EQ(reader.format().heightPx, 16);
  EXPECT_EQ(reader.format().scan, ScanMode::Interlaced);
  EXPECT_EQ(reader.format().fieldOrder, FieldOrder::BottomFirst);
  EXPECT_EQ(reader.format().fieldRate.numerator, 60000);
  EXPECT_EQ(reader.slotCount(), 4);
  Field out;
  EXPECT_EQ(reader.readLatest(out), ShmReadStatus::NotYet);
  for (std::uint64_t k = 0; k < 3; ++k) {
    Field f = makeField(format, k);
    f.marginViolations = static_cast<std::uint32_t>(k * 100);
    ASSERT_TRUE(writer.publish(f));
  }
  EXPECT_EQ(reader.publishedCount(), 3u);
  for (std::uint64_t p = 0; p < 3; ++p) {
    ASSERT_EQ(reader.read(p, out), ShmReadStatus::Ok);
    EXPECT_EQ(out.fieldNumber, p);
    EXPECT_TRUE(samePattern(out, format));
    EXPECT_EQ(out.marginViolations, p * 100);
    EXPECT_EQ(out.rasterHeightPx, 16);
  }
  EXPECT_EQ(reader.read(3, out), ShmReadStatus::NotYet);
}

TEST(ShmRing, OldPublicationsAreReportedOverwritten) {
  const StreamFormat format = testFormat(64, 16, ScanMode::Progressive, PixelFormat::Rgb8);
  ShmRingWriter writer(ringName("wrap"), format, 2);
  ShmRingReader reader(ringName("wrap"));
  for (std::uint64_t k = 0; k < 5; ++k) writer.publish(makeField(format, k));
  Field out;
  EXPECT_EQ(reader.read(0, out), ShmReadStatus::Overwritten);
  EXPECT_EQ(reader.read(4, out), ShmReadStatus::Ok);
  EXPECT_EQ(out.fieldNumber, 4u);
  EXPECT_EQ(reader.readLatest(out), ShmReadStatus::Ok);
  EXPECT_TRUE(samePattern(out, format));
  EXPECT_FALSE(writer.publish(makeField(testFormat(32, 16), 0)));  // wrong format: ignored
}

// The writer runs flat out while a reader copies the newest field again and again: every copy
// the reader accepts must be one whole field, never a mix of two.
TEST(ShmRing, ConcurrentReaderNeverAcceptsATornField) {
  const StreamFormat format = testFormat(64, 16);
  ShmRingWriter writer(ringName("race"), format, 2);
  ShmRingReader reader(ringName("race"));
  std::atomic<bool> done{false};
  std::uint64_t accepted = 0, busy = 0, bad = 0;
  std::thread readerThread([&] {
    Field out;
    // The last pass runs after the writer has finished, so on a machine too loaded for any race
    // to be won the reader still accepts one (whole) field.
    for (bool finished = false; !finished;) {
      finished = done.load(std::memory_order_acquire);
      const ShmReadStatus s = reader.readLatest(out);
      if (s == ShmReadStatus::Ok) {
        ++accepted;
        if (!samePattern(out, format)) ++bad;
      } else if (s == ShmReadStatus::Busy) {
        ++busy;
      }
    }
  });
  for (std::uint64_t k = 0; k < 3000; ++k) writer.publish(makeField(format, k % 64));
  done.store(true, std::memory_order_release);
  readerThread.join();
  EXPECT_EQ(bad, 0u);
  EXPECT_GT(accepted, 0u);
  RecordProperty("accepted", static_cast<int>(accepted));
  RecordProperty("busy", static_cast<int>(busy));
}

TEST(ShmRing, HeaderValidationNamesTheProblem) {
  const StreamFormat format = testFormat(64, 16);
  ShmRingWriter writer(ringName("hdr"), format, 3);
  std::vector<std::uint8_t> bytes(writer.mappedBytes());
  {
    ShmRingReader reader(ringName("hdr"));  // valid as written
  }
  // Build a valid header image to corrupt
  ShmRingHeader h{};
  std::memcpy(h.magic, kShmRingMagic, 8);
  h.version = 1;
  h.headerBytes = 256;
  h.slotCount = 3;
  h.slotHeaderBytes = 64;
  h.maxFieldBytes = 128 * 8;
  h.slotStrideBytes = 64 + 1024;
  h.widthPx = 64;
  h.heightPx = 16;
  h.pixelFormat = 2;
  h.scan = 1;
  h.fieldOrder = 1;
  h.fieldRateNumerator = 60000;
  h.fieldRateDenominator = 1001;
  const std::size_t size = 256 + 3 * (64 + 1024);
  auto check = [&](ShmRingHeader bad, std::size_t sz) {
    std::vector<std::uint8_t> b(std::max<std::size_t>(sz, sizeof bad));
    std::memcpy(b.data(), &bad, sizeof bad);
    return validateShmRingHeader(b.data(), sz);
  };
  EXPECT_EQ(check(h, size), "");
  ShmRingHeader bad = h;
  bad.magic[0] = 'X';
  EXPECT_NE(check(bad, size).find("magic"), std::string::npos);
  bad = h;
  bad.version = 2;
  EXPECT_NE(check(bad, size).find("version 2"), std::string::npos);
  EXPECT_NE(check(h, size - 1).find("truncated"), std::string::npos);
  bad = h;
  bad.slotCount = 0;
  EXPECT_NE(check(bad, size), "");
  bad = h;
  bad.slotStrideBytes = 64;
  EXPECT_NE(check(bad, size).find("stride"), std::string::npos);
  bad = h;
  bad.pixelFormat = 7;
  EXPECT_NE(check(bad, size), "");
  bad = h;
  bad.maxFieldBytes = 1u << 30;
  EXPECT_NE(check(bad, size), "");
  EXPECT_NE(validateShmRingHeader(nullptr, 0), "");
}

TEST(ShmRing, MissingRingIsAClearError) {
  try {
    ShmRingReader reader(ringName("absent"));
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
}

TEST(ShmRing, AsAHubSink) {
  const StreamFormat format = testFormat(64, 16);
  SinkHub hub(format);
  hub.add(std::make_unique<ShmRingSink>(ringName("hub"), 8));
  hub.start();
  {
    ShmRingReader reader(ringName("hub"));
    for (std::uint64_t k = 0; k < 3; ++k) hub.publish(makeField(format, k));
    while (hub.figures()[0].consumed + hub.figures()[0].droppedFull < 3) std::this_thread::yield();
    Field out;
    ASSERT_EQ(reader.readLatest(out), ShmReadStatus::Ok);
    EXPECT_TRUE(samePattern(out, format));
  }
  hub.stop();
}

}  // namespace
}  // namespace fieldcast::io
