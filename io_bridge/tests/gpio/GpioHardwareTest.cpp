// GPIO tests that need a real chip (label `hw`): they skip with the reason when there is none.
#include <io_bridge/GpioInput.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace fieldcast::io {
namespace {

TEST(GpioHardware, RequestsEdgeEventsOnARealLine) {
  if (listGpioChips().empty()) GTEST_SKIP() << "no /dev/gpiochip* on this machine";
  const char* spec = std::getenv("FIELDCAST_TEST_GPIO");
  if (spec == nullptr)
    GTEST_SKIP() << "set FIELDCAST_TEST_GPIO=gpiochipN:offset[:active_low][:pull_up] to name a free input line";
  GpioLineConfig config = parseGpioLineSpec(spec);
  config.consumer = "fieldcast-test";
  auto line = openGpiodEdgeLine(config);
  EXPECT_GE(line->eventFd(), 0);
  (void)line->level();
}

}  // namespace
}  // namespace fieldcast::io
