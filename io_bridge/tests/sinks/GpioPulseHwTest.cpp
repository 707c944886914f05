// Hardware test (label hw): pulses a real GPIO line through libgpiod. Skipped, with the reason,
// on machines without a GPIO chip or without a line named free to toggle.

#include <io_bridge/GpioPulseSink.h>

#include "TestFields.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

namespace fieldcast::io {
namespace {

using testing::makeField;
using testing::testFormat;

// Real hardware: set FIELDCAST_TEST_GPIO_CHIP and FIELDCAST_TEST_GPIO_LINE to a free line.
TEST(GpioPulseHardware, PulsesARealLine) {
  bool anyChip = false;
  for (const auto& e : std::filesystem::directory_iterator("/dev")) {
    if (e.path().filename().string().rfind("gpiochip", 0) == 0) anyChip = true;
  }
  if (!anyChip) GTEST_SKIP() << "no /dev/gpiochip* on this machine";
  const char* chip = std::getenv("FIELDCAST_TEST_GPIO_CHIP");
  const char* line = std::getenv("FIELDCAST_TEST_GPIO_LINE");
  if (!chip || !line)
    GTEST_SKIP() << "set FIELDCAST_TEST_GPIO_CHIP and FIELDCAST_TEST_GPIO_LINE to a line free to toggle";
  GpioPulseSink sink(std::make_unique<GpiodPulseLine>(chip, static_cast<unsigned>(std::atoi(line))), {});
  const StreamFormat f = testFormat(64, 16);
  sink.open(f);
  const TimePoint t0 = MonotonicClock::now() + std::chrono::milliseconds(5);
  for (std::uint64_t k = 0; k < 10; ++k) sink.consume(makeField(f, k, t0));
  sink.close();
  EXPECT_EQ(sink.pulses(), 10u);
}

}  // namespace
}  // namespace fieldcast::io
