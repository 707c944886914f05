// Device back ends: raw USB through the fake transfer source (real descriptor, real report bytes,
// unplug and replug), and the real evdev/hidraw/libusb code against what this machine has.
// Tests needing a real device are in HardwareTest.cpp (label hw).
#include <io_bridge/EvdevSource.h>
#include <io_bridge/HidrawSource.h>
#include <io_bridge/InputSources.h>
#include <io_bridge/StickInput.h>
#include <io_bridge/UsbHidSource.h>

#include "RealDescriptors.h"

#include <gtest/gtest.h>

#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <deque>
#include <filesystem>
#include <map>

namespace fieldcast::io {
namespace {

using namespace std::chrono_literals;
using namespace usages;

// The fake transfer source: completes queued interrupt-IN transfers with real report bytes, then
// reports the device gone (LIBUSB_TRANSFER_NO_DEVICE) when told to.
class FakeUsbTransport final : public UsbTransport {
 public:
  struct Bus {
    bool plugged = true;
    std::deque<std::vector<std::uint8_t>> reports;
    int opens = 0;
    bool started = false;
  };
  explicit FakeUsbTransport(Bus& bus) : mBus(bus) {
    ++mBus.opens;
    if (!mBus.plugged) throw std::runtime_error("no USB device 06a3:ff0d with an interrupt-IN interface of class 3");
  }
  std::string productName() const override { return "Saitek Cyborg Force"; }
  std::uint16_t vendorId() const override { return 0x06a3; }
  std::uint16_t productId() const override { return 0xff0d; }
  std::vector<std::uint8_t> reportDescriptor() override {
    return {std::begin(testdata::kSaitekFfbJoystick), std::end(testdata::kSaitekFfbJoystick)};
  }
  void startReading() override { mBus.started = true; }
  bool poll(Nanoseconds, const UsbReportCallback& onReport) override {
    if (!mBus.plugged) return false;
    if (!mBus.reports.empty()) {
      onReport(mBus.reports.front(), TimePoint{Nanoseconds{++mTick * 1000}});
      mBus.reports.pop_front();
    }
    return true;
  }

 private:
  Bus& mBus;
  std::int64_t mTick = 0;
};

TEST(UsbHidSource, DecodesInterruptReportsThroughTheSeam) {
  FakeUsbTransport::Bus bus;
  bus.reports = {{0x01, 0x80, 0x7f, 0x00, 0xff, 0x05, 0x38},  // X 128, Y 127, rudder 0, throttle 255
                 {0x01, 0x80},                                // short: refused and counted
                 {0x02, 0x01, 0x00},                          // report 2 (PID state): no stick controls change
                 {0x01, 0xff, 0x7f, 0x00, 0xff, 0x05, 0x38}};
  UsbHidSource source(std::make_unique<FakeUsbTransport>(bus));
  EXPECT_TRUE(bus.started);
  EXPECT_EQ(source.description().transport, InputTransport::Usb);
  EXPECT_EQ(source.description().vendorId, 0x06a3);
  ASSERT_NE(source.description().find(kThrottle), nullptr);
  std::vector<InputEvent> out;
  EXPECT_EQ(source.read(out, 1ms), ReadResult::Events);
  EXPECT_EQ(out.front(), (InputEvent{1000, kX, 128, InputEventType::Value}));
  out.clear();
  EXPECT_EQ(source.read(out, 1ms), ReadResult::Timeout);  // the short report
  EXPECT_EQ(source.stats().rejectedReports, 1u);
  source.read(out, 1ms);
  out.clear();
  EXPECT_EQ(source.read(out, 1ms), ReadResult::Events);
  ASSERT_EQ(out.size(), 2u);  // only X changed
  EXPECT_EQ(out[0].value, 255);
  bus.plugged = false;
  EXPECT_EQ(source.read(out, 1ms), ReadResult::Lost);
}

TEST(UsbHidSource, SurvivesUnplugAndReplug) {
  FakeUsbTransport::Bus bus;
  bus.reports = {{0x01, 0xff, 0x80, 0x80, 0x00, 0x00, 0xf0}};
  VirtualClock clock;
  StickInputOptions options;
  options.backoffMin = 50ms;
  StickInput input([&] { return std::make_unique<UsbHidSource>(std::make_unique<FakeUsbTransport>(bus)); },
                   StickProfile::generic(), options, clock);
  while (input.stats().frames < 1) input.step();
  EXPECT_DOUBLE_EQ(input.latest().roll, 1.0);
  EXPECT_DOUBLE_EQ(input.latest().throttle, 1.0);  // lever fully forward reads 0: inverted, full power
  bus.plugged = false;
  while (input.stats().losses < 1) input.step();
  EXPECT_EQ(input.latest().health, InputHealth::Holding);
  while (input.stats().failedOpens < 3) input.step();  // retries with backoff, all failing
  EXPECT_EQ(input.stats().connects, 1u);
  bus.plugged = true;
  bus.reports = {{0x01, 0x00, 0x80, 0x80, 0x00, 0x00, 0xf0}};
  while (input.stats().frames < 2) input.step();
  EXPECT_EQ(input.stats().connects, 2u);
  EXPECT_EQ(input.latest().health, InputHealth::Live);
  EXPECT_DOUBLE_EQ(input.latest().roll, -1.0);
}

TEST(HidrawSource, OneReportPerReadThroughASeqpacketSocket) {
  // SOCK_SEQPACKET keeps message boundaries: each read() returns one report, as hidraw does.
  int fds[2];
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, fds), 0);
  HidrawSource source(fds[0], testdata::kAsusGamepad, "Asus gamepad");
  EXPECT_EQ(source.description().transport, InputTransport::Hidraw);
  auto send = [&](std::vector<std::uint8_t> r) {
    ASSERT_EQ(::write(fds[1], r.data(), r.size()), static_cast<ssize_t>(r.size()));
  };
  send({0x01, 0x01, 0x20, 0x00, 0xff, 0x80, 0x80, 0x00, 0x00});  // button 1, hat East, X 0, Y 255
  send({0x01, 0x01});                                            // short: refused, counted
  send({0x01, 0x00, 0x80, 0x00, 0xff, 0x80, 0x80, 0x00, 0x00});  // button 1 released, hat centred (8)
  std::vector<InputEvent> out;
  const std::int64_t before = MonotonicClock::now().time_since_epoch().count();
  EXPECT_EQ(source.read(out, 10ms), ReadResult::Events);
  EXPECT_EQ(source.stats().rejectedReports, 1u);
  std::map<Usage, std::vector<std::int32_t>> seen;
  int syncs = 0;
  for (const InputEvent& e : out) {
    EXPECT_GE(e.tNs, before);  // stamped on CLOCK_MONOTONIC when read
    if (e.type == InputEventType::Sync) ++syncs;
    if (e.type == InputEventType::Value) seen[e.usage].push_back(e.value);
  }
  EXPECT_EQ(syncs, 2);
  EXPECT_EQ(seen[button(1)], (std::vector<std::int32_t>{1, 0}));
  EXPECT_EQ(seen[kHatSwitch], (std::vector<std::int32_t>{2, kHatCentred}));
  EXPECT_EQ(seen[kY], (std::vector<std::int32_t>{255}));
  ::close(fds[1]);  // the device goes away
  out.clear();
  EXPECT_EQ(source.read(out, 10ms), ReadResult::Lost);
}

TEST(UsbSelector, ParsesVendorProduct) {
  const UsbDeviceSelector s = parseUsbSelector("044f:0409");
  EXPECT_EQ(*s.vendorId, 0x044f);
  EXPECT_EQ(*s.productId, 0x0409);
  EXPECT_THROW(parseUsbSelector("044f"), std::runtime_error);
  EXPECT_THROW(parseUsbSelector("zz:0409"), std::runtime_error);
}

TEST(InputSources, NamesAreCheckedAtOnceAndDevicesWhenOpened) {
  VirtualClock clock;
  auto errorOf = [&](const std::string& spec) {
    try {
      auto factory = makeSourceFactory(spec, clock);
      (void)factory();
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(errorOf("usb:zz:01").find("expected vendor:product in hexadecimal"), std::string::npos);
  EXPECT_NE(errorOf("usb:class:300").find("expected usb:class:N"), std::string::npos);
  EXPECT_NE(errorOf("replay:/nonexistent.rec").find("/nonexistent.rec: cannot read"), std::string::npos);
  EXPECT_NE(errorOf("hidraw:/dev/null").find("not a hidraw device"), std::string::npos);
  EXPECT_NE(errorOf("evdev:/dev/null").find("not an evdev device"), std::string::npos);
  EXPECT_NE(errorOf("usb:class:255:descriptor=/nonexistent.hex").find("cannot read the report descriptor"),
            std::string::npos);
  EXPECT_TRUE(isReplaySpec("replay:x.rec"));
  EXPECT_FALSE(isReplaySpec("/dev/input/event3"));
  const std::string data = std::string(FIELDCAST_SOURCE_DIR) + "/tests/stick/data/";
  EXPECT_EQ(readHidDescriptorFile(data + "tca_yoke_boeing.hex").size(), sizeof(testdata::kTcaYokeBoeing));
  EXPECT_TRUE(std::equal(std::begin(testdata::kTcaYokeBoeing), std::end(testdata::kTcaYokeBoeing),
                         readHidDescriptorFile(data + "tca_yoke_boeing.hex").begin()));
  EXPECT_NO_THROW((void)makeSourceFactory("replay:" + data + "saitek_roll.rec:realtime", clock)());
}

TEST(RealBackends, LibusbRefusesAnAbsentDeviceWithTheReason) {
  // The real libusb code: no device 1234:5678 exists here (or libusb cannot start: also a reason).
  try {
    (void)openLibusbTransport(parseUsbSelector("1234:5678"));
    ADD_FAILURE() << "opened a device that does not exist";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_TRUE(what.find("1234:5678") != std::string::npos || what.find("libusb") != std::string::npos) << what;
  }
}

TEST(RealBackends, EvdevAndHidrawRefuseWhatIsNotTheirDevice) {
  try {
    EvdevSource s("/dev/null");
    ADD_FAILURE() << "/dev/null opened as evdev";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("evdev /dev/null: not an evdev device"), std::string::npos) << e.what();
  }
  try {
    HidrawSource s("/dev/null");
    ADD_FAILURE() << "/dev/null opened as hidraw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("hidraw /dev/null: not a hidraw device"), std::string::npos) << e.what();
  }
  EXPECT_THROW(EvdevSource("no stick has this name 7f3a"), std::runtime_error);
}

}  // namespace
}  // namespace fieldcast::io
