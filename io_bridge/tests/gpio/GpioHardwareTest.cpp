// GPIO tests that need a real chip (label `hw`): they skip with the reason when there is none.
// Lines are named by environment variables, as gpiochipN:offset:
//   FIELDCAST_TEST_GPIO        an input line free to request (optionally :active_low, :pull_up, ...)
//   FIELDCAST_TEST_GPIO_OUT    an output line free to toggle: driven and read back
//   FIELDCAST_TEST_GPIO_DRIVE  an output line wired to FIELDCAST_TEST_GPIO (a loopback pair): the
//                              input must see every level and edge the output drives
#include <io_bridge/GpioInput.h>
#include <io_bridge/GpioPulseSink.h>

#include <gpiod.h>
#include <poll.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace fieldcast::io {
namespace {

// The line an environment variable names, or a reason to skip.
std::string skipReason(const char* variable, const char* what) {
  if (listGpioChips().empty()) return "no /dev/gpiochip* on this machine";
  if (std::getenv(variable) == nullptr) return std::string("set ") + variable + "=gpiochipN:offset to name " + what;
  return {};
}

// Edges queued on `line` now, without waiting (its descriptor blocks: poll first).
std::vector<GpioEdge> queuedEdges(GpioEdgeLine& line) {
  std::vector<GpioEdge> edges;
  pollfd p{line.eventFd(), POLLIN, 0};
  while (::poll(&p, 1, 0) == 1 && line.readEdges(edges)) {
  }
  return edges;
}

TEST(GpioHardware, RequestsEdgeEventsOnARealLine) {
  if (const std::string why = skipReason("FIELDCAST_TEST_GPIO", "a free input line"); !why.empty()) GTEST_SKIP() << why;
  GpioLineConfig config = parseGpioLineSpec(std::getenv("FIELDCAST_TEST_GPIO"));
  config.consumer = "fieldcast-test";
  auto line = openGpiodEdgeLine(config);
  EXPECT_GE(line->eventFd(), 0);
  // Nothing drives the line here, so its level is unknown, but it is a level: reading it twice
  // with no edge in between gives the same answer.
  const bool first = line->level();
  if (queuedEdges(*line).empty()) {
    EXPECT_EQ(line->level(), first);
  }
}

TEST(GpioHardware, AnOutputLineReadsBackWhatItDrives) {
  // libgpiod v1 reads an output line's value back from the chip (gpiod_line_get_value on the
  // requested output), which shows the chip takes the level the pulse sink sets.
  if (const std::string why = skipReason("FIELDCAST_TEST_GPIO_OUT", "an output line free to toggle"); !why.empty()) {
    GTEST_SKIP() << why;
  }
  const GpioLineConfig config = parseGpioLineSpec(std::getenv("FIELDCAST_TEST_GPIO_OUT"));
  gpiod_chip* chip = gpiod_chip_open_lookup(config.chip.c_str());
  ASSERT_NE(chip, nullptr) << config.chip << ": " << std::strerror(errno);
  gpiod_line* line = gpiod_chip_get_line(chip, config.offset);
  ASSERT_NE(line, nullptr) << config.chip << " line " << config.offset << ": " << std::strerror(errno);
  ASSERT_EQ(gpiod_line_request_output(line, "fieldcast-test", 0), 0) << std::strerror(errno);
  EXPECT_EQ(gpiod_line_get_value(line), 0);
  for (int k = 0; k < 5; ++k) {
    ASSERT_EQ(gpiod_line_set_value(line, 1), 0);
    EXPECT_EQ(gpiod_line_get_value(line), 1) << "cycle " << k;
    ASSERT_EQ(gpiod_line_set_value(line, 0), 0);
    EXPECT_EQ(gpiod_line_get_value(line), 0) << "cycle " << k;
  }
  gpiod_line_release(line);
  gpiod_chip_close(chip);
}

TEST(GpioHardware, ALoopbackPairCarriesLevelsAndEdges) {
  if (const std::string why = skipReason("FIELDCAST_TEST_GPIO", "the input line of a loopback pair"); !why.empty()) {
    GTEST_SKIP() << why;
  }
  if (std::getenv("FIELDCAST_TEST_GPIO_DRIVE") == nullptr) {
    GTEST_SKIP() << "set FIELDCAST_TEST_GPIO_DRIVE=gpiochipN:offset to an output line wired to FIELDCAST_TEST_GPIO";
  }
  GpioLineConfig inputConfig = parseGpioLineSpec(std::getenv("FIELDCAST_TEST_GPIO"));
  inputConfig.consumer = "fieldcast-test";
  const GpioLineConfig driveConfig = parseGpioLineSpec(std::getenv("FIELDCAST_TEST_GPIO_DRIVE"));
  GpiodPulseLine drive(driveConfig.chip, driveConfig.offset);  // requested low
  auto input = openGpiodEdgeLine(inputConfig);
  (void)queuedEdges(*input);  // anything queued before the pair settled
  std::vector<GpioEdge> edges;
  TimePoint previous{};
  for (int k = 0; k < 10; ++k) {
    const bool high = k % 2 == 0;
    const TimePoint before = MonotonicClock::now();
    drive.set(high);
    // The hang guard only: a wired pair delivers the edge within microseconds.
    pollfd p{input->eventFd(), POLLIN, 0};
    ASSERT_EQ(::poll(&p, 1, 5000), 1) << "no edge on " << input->name() << " after driving it "
                                      << (high ? "high" : "low") << ": are the lines wired together?";
    edges.clear();
    ASSERT_TRUE(input->readEdges(edges));
    ASSERT_EQ(edges.size(), 1u) << "cycle " << k;
    const bool logicalHigh = high != inputConfig.activeLow;
    EXPECT_EQ(edges[0].kind, logicalHigh ? GpioEdgeKind::Rising : GpioEdgeKind::Falling) << "cycle " << k;
    EXPECT_GE(edges[0].time, before) << "an edge stamped before the line was driven";
    EXPECT_GE(edges[0].time, previous);
    previous = edges[0].time;
    EXPECT_EQ(input->level(), logicalHigh) << "cycle " << k;
  }
}

}  // namespace
}  // namespace fieldcast::io
