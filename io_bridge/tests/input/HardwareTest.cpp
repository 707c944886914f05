// Tests that need a real stick (label `hw`): each skips with the reason when there is none here.
#include <io_bridge/EvdevSource.h>
#include <io_bridge/HidrawSource.h>
#include <io_bridge/UsbHidSource.h>
#include <io_bridge/UsbHotplug.h>

#include <gtest/gtest.h>

#include <cstdlib>

namespace fieldcast::io {
namespace {

using namespace std::chrono_literals;

TEST(Hardware, EvdevJoystick) {
  const char* wanted = std::getenv("FIELDCAST_TEST_EVDEV");
  std::string spec = wanted != nullptr ? wanted : "";
  if (spec.empty()) {
    for (const EvdevDeviceInfo& d : listEvdevDevices()) {
      if (d.isJoystick) spec = d.path;
    }
  }
  if (spec.empty())
    GTEST_SKIP() << "no evdev joystick here (no readable /dev/input/event* reports X/Y or stick buttons)";
  EvdevSource source(spec);
  EXPECT_FALSE(source.description().controls.empty());
  std::vector<InputEvent> out;
  EXPECT_EQ(source.read(out, 10ms), ReadResult::Events);  // the state at open
  const auto now = MonotonicClock::now().time_since_epoch().count();
  EXPECT_LE(out.back().tNs, now);
}

TEST(Hardware, HidrawDevice) {
  const char* wanted = std::getenv("FIELDCAST_TEST_HIDRAW");
  if (wanted == nullptr) {
    GTEST_SKIP() << (listHidrawDevices().empty() ? "no /dev/hidraw* device here"
                                                 : "set FIELDCAST_TEST_HIDRAW=/dev/hidrawN to pick the stick");
  }
  HidrawSource source(wanted);
  EXPECT_FALSE(source.reportDescriptor().empty());
}

TEST(Hardware, UsbHidDevice) {
  const char* wanted = std::getenv("FIELDCAST_TEST_USB");
  if (wanted == nullptr) GTEST_SKIP() << "no USB stick given (set FIELDCAST_TEST_USB=vid:pid, and detach rights)";
  UsbDeviceSelector sel = parseUsbSelector(wanted);
  sel.detachKernelDriver = true;
  UsbHidSource source(openLibusbTransport(sel));
  std::vector<InputEvent> out;
  (void)source.read(out, 100ms);
  EXPECT_FALSE(source.description().controls.empty());
}

// Needs a person: plug the device in (or unplug and replug it) within 30 s of the start.
TEST(Hardware, UsbHotplugArrival) {
  const char* wanted = std::getenv("FIELDCAST_TEST_USB_REPLUG");
  if (wanted == nullptr) GTEST_SKIP() << "set FIELDCAST_TEST_USB_REPLUG=vid:pid and replug that device within 30 s";
  auto bus = openLibusbHotplugBus();
  if (!bus->hasHotplug()) GTEST_SKIP() << "libusb has no hotplug here: the backoff poll alone reconnects";
  const auto watch = watchUsbArrivals(std::move(bus), parseUsbSelector(wanted));
  ASSERT_NE(watch, nullptr);
  bool arrived = false;
  for (int k = 0; k < 300 && !arrived; ++k) arrived = watch->waitForArrival(100ms);
  EXPECT_TRUE(arrived) << "no arrival of " << wanted << " announced within 30 s";
}

}  // namespace
}  // namespace fieldcast::io
