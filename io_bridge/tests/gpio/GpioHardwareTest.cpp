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
  if (spec == nullptr) GTEST_SKIP() << "set FIELDCAST_TEST_GPIO=gpiochipN:offset to name a free input line";
  const std::string s = spec;
  const auto colon = s.find(':');
  ASSERT_NE(colon, std::string::npos) << "FIELDCAST_TEST_GPIO: expected chip:offset";
  auto line =
      openGpiodEdgeLine(GpioLineConfig{s.substr(0, colon), static_cast<unsigned>(std::stoul(s.substr(colon + 1))),
                                       false, GpioBias::AsIs, "fieldcast-test"});
  EXPECT_GE(line->eventFd(), 0);
  (void)line->level();
}

}  // namespace
}  // namespace fieldcast::io
