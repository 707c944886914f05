// Hardware tests (label hw): pulse a real GPIO line through libgpiod and read it back. Skipped,
// with the reason, on machines without a GPIO chip or without lines named for the test:
//   FIELDCAST_TEST_GPIO_CHIP, FIELDCAST_TEST_GPIO_LINE  an output line free to toggle
//   FIELDCAST_TEST_GPIO_SENSE=gpiochipN:offset            optional: an input line wired to it, which
//                                                         must see every pulse's two edges

#include <io_bridge/GpioInput.h>
#include <io_bridge/GpioPulseSink.h>

#include "TestFields.h"

#include <gpiod.h>
#include <poll.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace fieldcast::io {
namespace {

using testing::makeField;
using testing::testFormat;

// The output line named for the test, or a reason to skip in `why`.
struct NamedLine {
  std::string chip;
  unsigned offset = 0;
  std::string why;
};

NamedLine namedOutputLine() {
  bool anyChip = false;
  for (const auto& e : std::filesystem::directory_iterator("/dev")) {
    if (e.path().filename().string().rfind("gpiochip", 0) == 0) anyChip = true;
  }
  if (!anyChip) return {"", 0, "no /dev/gpiochip* on this machine"};
  const char* chip = std::getenv("FIELDCAST_TEST_GPIO_CHIP");
  const char* line = std::getenv("FIELDCAST_TEST_GPIO_LINE");
  if (!chip || !line)
    return {"", 0, "set FIELDCAST_TEST_GPIO_CHIP and FIELDCAST_TEST_GPIO_LINE to a line free to toggle"};
  return {chip, static_cast<unsigned>(std::atoi(line)), ""};
}

// An output line requested as GpiodPulseLine requests it (libgpiod v1, output, initially low)
// that reads the chip's value back after every set() and records both.
class ReadbackPulseLine final : public PulseLine {
 public:
  ReadbackPulseLine(const std::string& chip, unsigned offset) {
    mChip = gpiod_chip_open_lookup(chip.c_str());
    if (!mChip) throw std::runtime_error(chip + ": " + std::strerror(errno));
    mLine = gpiod_chip_get_line(mChip, offset);
    if (!mLine || gpiod_line_request_output(mLine, "fieldcast-test", 0) != 0) {
      const int e = errno;
      gpiod_chip_close(mChip);
      throw std::runtime_error(chip + " line " + std::to_string(offset) + ": " + std::strerror(e));
    }
  }
  ~ReadbackPulseLine() override {
    gpiod_line_release(mLine);
    gpiod_chip_close(mChip);
  }
  ReadbackPulseLine(const ReadbackPulseLine&) = delete;
  ReadbackPulseLine& operator=(const ReadbackPulseLine&) = delete;

  void set(bool high) noexcept override {
    gpiod_line_set_value(mLine, high ? 1 : 0);
    levels.emplace_back(high, gpiod_line_get_value(mLine));
  }
  std::string describe() const override { return "read-back test line"; }

  std::vector<std::pair<bool, int>> levels;  ///< (set, read back) per set()

 private:
  gpiod_chip* mChip = nullptr;
  gpiod_line* mLine = nullptr;
};

TEST(GpioPulseHardware, PulsesARealLine) {
  const NamedLine out = namedOutputLine();
  if (!out.why.empty()) GTEST_SKIP() << out.why;
  // With a sense line wired to the output, every pulse is seen: a rising edge no earlier than the
  // field's display time, then a falling edge no earlier than display time + width.
  std::unique_ptr<GpioEdgeLine> sense;
  if (const char* spec = std::getenv("FIELDCAST_TEST_GPIO_SENSE")) {
    GpioLineConfig config = parseGpioLineSpec(spec);
    config.consumer = "fieldcast-test";
    sense = openGpiodEdgeLine(config);
  }
  const GpioPulseOptions options;
  GpioPulseSink sink(std::make_unique<GpiodPulseLine>(out.chip, out.offset), options);
  const StreamFormat f = testFormat(64, 16);
  sink.open(f);
  const TimePoint t0 = MonotonicClock::now() + std::chrono::milliseconds(5);
  std::vector<TimePoint> shown;
  for (std::uint64_t k = 0; k < 10; ++k) {
    const Field field = makeField(f, k, t0);
    shown.push_back(field.displayTime);
    sink.consume(field);
  }
  sink.close();
  EXPECT_EQ(sink.pulses() + sink.latePulses(), 10u);
  EXPECT_EQ(sink.pulses(), 10u) << "fields were late: run with real-time priority";
  if (!sense) {
    std::printf("FIELDCAST_TEST_GPIO_SENSE not set: the pulses were not read back on a wired input\n");
    return;
  }
  std::vector<GpioEdge> edges;
  pollfd p{sense->eventFd(), POLLIN, 0};
  while (::poll(&p, 1, 0) == 1 && sense->readEdges(edges)) {
  }
  ASSERT_EQ(edges.size(), 2 * sink.pulses()) << "edges seen on the sense line";
  for (std::size_t k = 0; k < sink.pulses(); ++k) {
    const GpioEdge& rise = edges[2 * k];
    const GpioEdge& fall = edges[2 * k + 1];
    EXPECT_EQ(rise.kind, GpioEdgeKind::Rising) << "pulse " << k;
    EXPECT_EQ(fall.kind, GpioEdgeKind::Falling) << "pulse " << k;
    EXPECT_GE(rise.time, shown[k]) << "pulse " << k << " rose before its field's display time";
    EXPECT_GE(fall.time, shown[k] + options.width) << "pulse " << k << " fell before its width was over";
  }
  EXPECT_FALSE(sense->level());
}

TEST(GpioPulseHardware, TheLineTakesEveryLevelTheSinkSets) {
  const NamedLine out = namedOutputLine();
  if (!out.why.empty()) GTEST_SKIP() << out.why;
  auto owned = std::make_unique<ReadbackPulseLine>(out.chip, out.offset);
  ReadbackPulseLine& line = *owned;
  GpioPulseSink sink(std::move(owned), {});
  const StreamFormat f = testFormat(64, 16);
  sink.open(f);
  const TimePoint t0 = MonotonicClock::now() + std::chrono::milliseconds(5);
  for (std::uint64_t k = 0; k < 10; ++k) sink.consume(makeField(f, k, t0));
  sink.close();
  // open: low; each pulse: high then low; close: low. Each read back as set.
  std::vector<bool> expected{false};
  for (std::uint64_t k = 0; k < sink.pulses(); ++k) {
    expected.push_back(true);
    expected.push_back(false);
  }
  expected.push_back(false);
  ASSERT_EQ(line.levels.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(line.levels[i].first, expected[i]) << "set " << i;
    EXPECT_EQ(line.levels[i].second, expected[i] ? 1 : 0) << "set " << i << ": the chip reads back another level";
  }
}

}  // namespace
}  // namespace fieldcast::io
