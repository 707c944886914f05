#include <io_bridge/Y4mSink.h>

#include "TestFields.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

namespace fieldcast::io {
namespace {

using testing::makeField;
using testing::testFormat;

std::string readAll(const std::filesystem::path& p) {
  // Through a string stream: the istreambuf_iterator form set off GCC 12's -Wnull-dereference
  // inside libstdc++ in every build.
  std::ifstream in(p, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return std::move(bytes).str();
}

std::filesystem::path tempPath(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("fieldcast_y4m_" + std::to_string(::getpid()) + "_" + name);
}

TEST(Y4mSink, HeaderOfNtscInterlaced) {
  StreamFormat f = testFormat(720, 486);
  EXPECT_EQ(Y4mSink::header(f, Y4mChroma::C420),
            "YUV4MPEG2 W720 H486 F30000:1001 Ib A10:11 C420mpeg2 XCOLORRANGE=LIMITED\n");
  f.fieldOrder = FieldOrder::TopFirst;
  EXPECT_EQ(Y4mSink::header(f, Y4mChroma::C422),
            "YUV4MPEG2 W720 H486 F30000:1001 It A10:11 C422 XCOLORRANGE=LIMITED\n");
}

TEST(Y4mSink, HeaderOfProgressiveHd) {
  StreamFormat f = testFormat(1920, 1080, ScanMode::Progressive);
  EXPECT_EQ(Y4mSink::header(f, Y4mChroma::C420),
            "YUV4MPEG2 W1920 H1080 F60000:1001 Ip A1:1 C420mpeg2 XCOLORRANGE=LIMITED\n");
  f.fieldRate = {50, 1};
  f.scan = ScanMode::Interlaced;
  EXPECT_EQ(Y4mSink::header(f, Y4mChroma::C420).substr(0, 32), "YUV4MPEG2 W1920 H1080 F25:1 Ib A");
}

// 4:2:2 output of UYVY fields is lossless: every byte of the file is predictable.
TEST(Y4mSink, WeavesTwoFieldsIntoEachFrame) {
  const StreamFormat f = testFormat(16, 6);
  const auto path = tempPath("weave.y4m");
  Y4mSink sink({path, Y4mChroma::C422});
  sink.open(f);
  for (std::uint64_t k = 0; k < 4; ++k) ASSERT_EQ(sink.consume(makeField(f, k)), SinkStatus::Ok);
  sink.close();
  EXPECT_EQ(sink.framesWritten(), 2u);
  EXPECT_EQ(sink.incompleteFrames(), 0u);

  const std::string bytes = readAll(path);
  const std::string head = Y4mSink::header(f, Y4mChroma::C422);
  const std::size_t frameBytes = 6 + 16 * 6 + 2 * (8 * 6);
  ASSERT_EQ(bytes.size(), head.size() + 2 * frameBytes);
  for (int frame = 0; frame < 2; ++frame) {
    const std::size_t base = head.size() + static_cast<std::size_t>(frame) * frameBytes;
    ASSERT_EQ(bytes.substr(base, 6), "FRAME\n");
    for (int row = 0; row < 6; ++row) {
      // Bottom field first: field 2·frame carries the odd rows, field 2·frame+1 the even rows.
      const std::uint64_t k = 2 * static_cast<std::uint64_t>(frame) + (row % 2 == 1 ? 0 : 1);
      for (int x = 0; x < 16; ++x) {
        const auto luma = static_cast<std::uint8_t>(bytes[base + 6 + static_cast<std::size_t>(row) * 16 + x]);
        ASSERT_EQ(luma, testing::patternByte(k, row, 2 * x + 1)) << "frame " << frame << " row " << row << " x " << x;
      }
      for (int c = 0; c < 8; ++c) {
        const auto cb = static_cast<std::uint8_t>(bytes[base + 6 + 96 + static_cast<std::size_t>(row) * 8 + c]);
        const auto cr = static_cast<std::uint8_t>(bytes[base + 6 + 96 + 48 + static_cast<std::size_t>(row) * 8 + c]);
        ASSERT_EQ(cb, testing::patternByte(k, row, 4 * c));
        ASSERT_EQ(cr, testing::patternByte(k, row, 4 * c + 2));
      }
    }
  }
  std::filesystem::remove(path);
}

// 4:2:0 of an interlaced frame subsamples each field on its own: chroma rows alternate fields.
TEST(Y4mSink, Interlaced420KeepsTheFieldsChromaApart) {
  StreamFormat f = testFormat(8, 8);
  const auto path = tempPath("420.y4m");
  Y4mSink sink({path, Y4mChroma::C420});
  sink.open(f);
  for (std::uint64_t k = 0; k < 2; ++k) {
    Field field = makeField(f, k);
    const std::uint8_t cb = field.parity == FieldParity::Top ? 60 : 200;
    for (int r = 0; r < field.image.heightPx(); ++r) {
      for (int i = 0; i < 4; ++i) field.image.row(r)[4 * i] = cb;
    }
    sink.consume(field);
  }
  sink.close();
  const std::string bytes = readAll(path);
  const std::size_t base = Y4mSink::header(f, Y4mChroma::C420).size() + 6 + 64;
  ASSERT_EQ(bytes.size(), base + 2 * 16);
  for (int c = 0; c < 4; ++c) {
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(static_cast<std::uint8_t>(bytes[base + static_cast<std::size_t>(c) * 4 + i]), c % 2 == 0 ? 60 : 200)
          << "chroma row " << c;
    }
  }
  std::filesystem::remove(path);
}

TEST(Y4mSink, ALostFieldStillWritesItsFrame) {
  const StreamFormat f = testFormat(16, 6);
  const auto path = tempPath("lost.y4m");
  Y4mSink sink({path, Y4mChroma::C422});
  sink.open(f);
  for (std::uint64_t k : {0u, 1u, 2u, 4u, 5u}) sink.consume(makeField(f, k));  // field 3 lost
  sink.close();
  EXPECT_EQ(sink.framesWritten(), 3u);
  EXPECT_EQ(sink.incompleteFrames(), 1u);
  std::filesystem::remove(path);
}

// Bytes of the stream header line, newline included.
std::uintmax_t headerBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::getline(in, line);
  return line.size() + 1;
}

TEST(Y4mSink, WholeMissedFramesAreRepeatedSoTheFileKeepsTime) {
  const StreamFormat f = testFormat(16, 6);
  const auto path = tempPath("gap.y4m");
  Y4mSink sink({path, Y4mChroma::C422});
  sink.open(f);
  for (std::uint64_t k : {0u, 1u, 6u, 7u}) sink.consume(makeField(f, k));  // frames 1 and 2 missed
  sink.close();
  EXPECT_EQ(sink.framesWritten(), 4u);
  EXPECT_EQ(sink.framesRepeated(), 2u);
  EXPECT_EQ(sink.incompleteFrames(), 0u);
  // Each frame is "FRAME\n" + 16×6 luma + 2 × 8×6 chroma.
  EXPECT_EQ(std::filesystem::file_size(path), headerBytes(path) + 4 * (6 + 16 * 6 * 2));
  std::filesystem::remove(path);
}

// A Y4M sink (4:2:2) fed `fields` in order, told where the schedule starts and ends when given:
// its figures and the file's bytes after the header.
struct ScheduledRun {
  std::uint64_t written = 0, repeated = 0, incomplete = 0;
  std::string frames;
};
ScheduledRun runSchedule(const StreamFormat& f, const std::string& name, std::optional<std::uint64_t> start,
                         const std::vector<Field>& fields, std::optional<std::uint64_t> end) {
  const auto path = tempPath(name + ".y4m");
  Y4mSink sink({path, Y4mChroma::C422});
  sink.open(f);
  if (start) sink.scheduleStarted(*start);
  for (const Field& field : fields) sink.consume(field);
  if (end) sink.scheduleEnded(*end);
  sink.close();
  ScheduledRun run{sink.framesWritten(), sink.framesRepeated(), sink.incompleteFrames(), readAll(path)};
  run.frames.erase(0, headerBytes(path));
  std::filesystem::remove(path);
  return run;
}

// Fields first … last − 1.
std::vector<Field> fieldsFrom(const StreamFormat& f, std::uint64_t first, std::uint64_t last) {
  std::vector<Field> fields;
  for (std::uint64_t k = first; k < last; ++k) fields.push_back(makeField(f, k));
  return fields;
}

TEST(Y4mSink, FramesMissedAtTheEndOfTheScheduleAreRepeatedToo) {
  const StreamFormat f = testFormat(16, 6);
  const std::size_t frameBytes = 6 + 16 * 6 * 2;
  // Fields 0–3 came, the schedule ended before field 10: frames 2, 3 and 4 never came.
  const ScheduledRun gap = runSchedule(f, "end_gap", std::nullopt, fieldsFrom(f, 0, 4), 10);
  EXPECT_EQ(gap.written, 5u);
  EXPECT_EQ(gap.repeated, 3u);
  EXPECT_EQ(gap.frames.size(), 5 * frameBytes);
  // Field 2 came without its partner and the schedule ended before field 7, inside frame 3:
  // frame 1 is written with one field, frames 2 and 3 repeat it.
  const ScheduledRun half = runSchedule(f, "end_half", std::nullopt, fieldsFrom(f, 0, 3), 7);
  EXPECT_EQ(half.written, 4u);
  EXPECT_EQ(half.repeated, 2u);
  EXPECT_EQ(half.incomplete, 1u);
  EXPECT_EQ(half.frames.size(), 4 * frameBytes);
  // Every field came: nothing to repeat.
  const ScheduledRun full = runSchedule(f, "end_full", std::nullopt, fieldsFrom(f, 0, 6), 6);
  EXPECT_EQ(full.written, 3u);
  EXPECT_EQ(full.repeated, 0u);
}

TEST(Y4mSink, FramesMissedAtTheStartOfTheScheduleShowTheFirstPicture) {
  const StreamFormat f = testFormat(16, 6);
  const std::size_t frameBytes = 6 + 16 * 6 * 2;
  // The schedule starts at field 0; the first field made is 5 (frame 2, its second field).
  const ScheduledRun gap = runSchedule(f, "start_gap", 0, fieldsFrom(f, 5, 8), std::nullopt);
  EXPECT_EQ(gap.written, 4u);
  EXPECT_EQ(gap.repeated, 2u);
  ASSERT_EQ(gap.frames.size(), 4 * frameBytes);
  // Frames 0 and 1 are frame 2's picture
  const std::string first = gap.frames.substr(0, frameBytes);
  EXPECT_EQ(gap.frames.substr(frameBytes, frameBytes), first);
  EXPECT_EQ(gap.frames.substr(2 * frameBytes, frameBytes), first);
  EXPECT_NE(gap.frames.substr(3 * frameBytes, frameBytes), first);
  // A move onto another lock inside the first frame: its partner field comes as 1003. Nothing
  // lies before the first frame in either numbering.
  std::vector<Field> moved = fieldsFrom(f, 0, 1);
  moved.push_back(makeField(f, 1003));
  moved.back().renumbered = true;
  const ScheduledRun move = runSchedule(f, "start_moved", 0, moved, std::nullopt);
  EXPECT_EQ(move.written, 1u);
  EXPECT_EQ(move.repeated, 0u);
  // A channel joining a frame lock starts its schedule at the others' field: nothing before it.
  const ScheduledRun joined = runSchedule(f, "start_joined", 1000, fieldsFrom(f, 1000, 1004), std::nullopt);
  EXPECT_EQ(joined.written, 2u);
  EXPECT_EQ(joined.repeated, 0u);
}

TEST(Y4mSink, FieldsRenumberedByAMoveOntoAnotherLockFillNothing) {
  // Fields 0–2, then the field clock moves onto another lock: the field after 2 is 1003 (odd,
  // as 3 would have been), and it completes the frame field 2 began.
  const StreamFormat f = testFormat(16, 6);
  const auto path = tempPath("renumbered.y4m");
  Y4mSink sink({path, Y4mChroma::C422});
  sink.open(f);
  for (std::uint64_t k : {0u, 1u, 2u}) sink.consume(makeField(f, k));
  Field moved = makeField(f, 1003);
  moved.renumbered = true;
  sink.consume(moved);
  for (std::uint64_t k : {1004u, 1005u}) sink.consume(makeField(f, k));
  sink.close();
  EXPECT_EQ(sink.framesWritten(), 3u);
  EXPECT_EQ(sink.framesRepeated(), 0u);
  EXPECT_EQ(sink.incompleteFrames(), 0u);
  std::filesystem::remove(path);
}

TEST(Y4mSink, ProgressiveGapsAreFilledToo) {
  const StreamFormat f = testFormat(16, 6, ScanMode::Progressive);
  const auto path = tempPath("gap_p.y4m");
  Y4mSink sink({path, Y4mChroma::C420});
  sink.open(f);
  for (std::uint64_t k : {3u, 4u, 7u}) sink.consume(makeField(f, k));  // starts late: no fill before 3
  sink.close();
  EXPECT_EQ(sink.framesWritten(), 5u);
  EXPECT_EQ(sink.framesRepeated(), 2u);
  std::filesystem::remove(path);
}

TEST(Y4mSink, UnwritableFolderIsAClearError) {
  Y4mSink sink({"/nonexistent-dir/out.y4m", Y4mChroma::C420});
  try {
    sink.open(testFormat(16, 6));
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldcast::io
