// Device back ends: raw USB through the fake transfer source (real descriptor, real report bytes,
// unplug and replug), and the real evdev/hidraw/libusb code against what this machine has.
// Tests needing a real device are in HardwareTest.cpp (label hw).
#include <io_bridge/EvdevSource.h>
#include <io_bridge/HidReportDescriptor.h>
#include <io_bridge/HidrawSource.h>
#include <io_bridge/InputSources.h>
#include <io_bridge/StickInput.h>
#include <io_bridge/UsbHidSource.h>
#include <io_bridge/UsbHotplug.h>

#include "RealDescriptors.h"

#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>

#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
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

// The fake hotplug bus: says whether it has hotplug, records the registration, and delivers an
// arrival (plugging the fake device in) from handleEvents() as libusb does.
class FakeHotplugBus final : public UsbHotplugBus {
 public:
  struct State {
    bool capable = true;
    int registrations = 0;
    std::optional<std::uint16_t> vendorId, productId;
    bool arrivalPending = false;
    FakeUsbTransport::Bus* usb = nullptr;
  };
  explicit FakeHotplugBus(State& state) : mState(state) {}
  bool hasHotplug() const override { return mState.capable; }
  void watchArrivals(std::optional<std::uint16_t> vendorId, std::optional<std::uint16_t> productId,
                     std::function<void()> onArrival) override {
    ++mState.registrations;
    mState.vendorId = vendorId;
    mState.productId = productId;
    mOnArrival = std::move(onArrival);
  }
  void handleEvents(Nanoseconds) override {
    if (!mState.arrivalPending) return;
    mState.arrivalPending = false;
    mState.usb->plugged = true;
    mOnArrival();
  }

 private:
  State& mState;
  std::function<void()> mOnArrival;
};

TEST(UsbHotplug, RegistersForTheDeviceOnlyWhereLibusbHasHotplug) {
  FakeHotplugBus::State state;
  const UsbDeviceSelector stick = parseUsbSelector("06a3:ff0d");
  EXPECT_NE(watchUsbArrivals(std::make_unique<FakeHotplugBus>(state), stick), nullptr);
  EXPECT_EQ(state.registrations, 1);
  EXPECT_EQ(state.vendorId, std::optional<std::uint16_t>(0x06a3));
  EXPECT_EQ(state.productId, std::optional<std::uint16_t>(0xff0d));
  state.capable = false;  // e.g. no udev/netlink: no watch, the poll alone
  EXPECT_EQ(watchUsbArrivals(std::make_unique<FakeHotplugBus>(state), stick), nullptr);
  EXPECT_EQ(state.registrations, 1);
  // Sources other than usb: have no watch; the real libusb answers for usb: without a device.
  EXPECT_EQ(makeArrivalWatch("/dev/input/event5"), nullptr);
  EXPECT_EQ(makeArrivalWatch("hidraw:/dev/hidraw0"), nullptr);
}

// The stick is lost with a 10 s backoff; it comes back after 1 s. With hotplug the arrival reopens
// it at once; without, or when the arrival is never announced, the poll finds it at the backoff.
enum class Replug { Announced, Unannounced, NoHotplug };
struct ReplugRun {
  TimePoint lostAt{}, reconnectedAt{};
  std::uint64_t arrivals = 0;
};

ReplugRun replugAfterOneSecond(Replug how) {
  FakeUsbTransport::Bus bus;
  bus.reports = {{0x01, 0xff, 0x80, 0x80, 0x00, 0x00, 0xf0}};
  FakeHotplugBus::State state;
  state.capable = how != Replug::NoHotplug;
  state.usb = &bus;
  VirtualClock clock;
  StickInputOptions options;
  options.backoffMin = 10s;
  options.backoffMax = 10s;
  options.arrivals = watchUsbArrivals(std::make_unique<FakeHotplugBus>(state), parseUsbSelector("06a3:ff0d"));
  StickInput input([&] { return std::make_unique<UsbHidSource>(std::make_unique<FakeUsbTransport>(bus)); },
                   StickProfile::generic(), options, clock);
  while (input.stats().frames < 1) input.step();
  bus.plugged = false;
  while (input.stats().losses < 1) input.step();
  ReplugRun run;
  run.lostAt = clock.now();
  const TimePoint replug = clock.now() + 1s;
  for (int steps = 0; input.stats().connects < 2 && clock.now() < run.lostAt + 60s && steps < 100000; ++steps) {
    if (clock.now() >= replug && !bus.plugged && !state.arrivalPending) {
      if (how == Replug::Announced) {
        state.arrivalPending = true;  // the kernel announces it; the bus plugs it in when handled
      } else {
        bus.plugged = true;
      }
    }
    input.step();
  }
  run.reconnectedAt = clock.now();
  run.arrivals = input.stats().arrivals;
  return run;
}

TEST(UsbHotplug, AnArrivalReopensAtOnceInsteadOfAtTheNextPoll) {
  const ReplugRun run = replugAfterOneSecond(Replug::Announced);
  EXPECT_EQ(run.arrivals, 1u);
  EXPECT_GE(run.reconnectedAt - run.lostAt, 1s);
  EXPECT_LT(run.reconnectedAt - run.lostAt, 1s + 100ms);  // within a read timeout of the arrival
}

TEST(UsbHotplug, WithoutHotplugThePollStillReconnects) {
  for (const Replug how : {Replug::NoHotplug, Replug::Unannounced}) {
    const ReplugRun run = replugAfterOneSecond(how);
    EXPECT_EQ(run.arrivals, 0u);
    EXPECT_GE(run.reconnectedAt - run.lostAt, 10s);  // at the backoff poll
    EXPECT_LT(run.reconnectedAt - run.lostAt, 11s) << (how == Replug::NoHotplug ? "no hotplug" : "not announced");
  }
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

TEST(InputSources, AHidSocketIsReadLikeHidrawAndRetriedLikeAnUnpluggedDevice) {
  VirtualClock clock;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("hidsocket_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string descriptor = (dir / "asus.bin").string();
  std::ofstream(descriptor, std::ios::binary)
      .write(reinterpret_cast<const char*>(testdata::kAsusGamepad), sizeof testdata::kAsusGamepad);
  const std::string path = (dir / "stick.sock").string();
  const std::string spec = "hidsocket:" + path + ":descriptor=" + descriptor;
  // The name is checked at once; the device (the server) only when opened
  EXPECT_THROW((void)makeSourceFactory("hidsocket:" + path, clock), std::runtime_error);
  auto factory = makeSourceFactory(spec, clock);
  try {
    (void)factory();
    ADD_FAILURE() << "connected to a socket nobody listens on";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  // The device server: a listening SOCK_SEQPACKET socket, one report per message
  const int server = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, path.c_str(), sizeof address.sun_path - 1);
  ASSERT_EQ(::bind(server, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(::listen(server, 1), 0);
  std::unique_ptr<InputSource> source = factory();
  const int device = ::accept(server, nullptr, nullptr);
  ASSERT_GE(device, 0);
  EXPECT_EQ(source->description().transport, InputTransport::Hidraw);
  const std::uint8_t report[] = {0x01, 0x00, 0x80, 0xff, 0x80, 0x80, 0x80, 0x00, 0x00};  // X full right
  ASSERT_EQ(::write(device, report, sizeof report), static_cast<ssize_t>(sizeof report));
  std::vector<InputEvent> out;
  EXPECT_EQ(source->read(out, 100ms), ReadResult::Events);
  std::map<Usage, std::int32_t> seen;
  for (const InputEvent& e : out)
    if (e.type == InputEventType::Value) seen[e.usage] = e.value;
  EXPECT_EQ(seen[kX], 255);
  ::close(device);  // the server goes away: the stick input's reconnect takes over
  out.clear();
  EXPECT_EQ(source->read(out, 100ms), ReadResult::Lost);
  ::close(server);
  std::filesystem::remove_all(dir);
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

// A file of `text` in the test's temporary folder; returns its path.
std::string writeFile(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("fieldcast_hid_" + name);
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

std::string readError(const std::string& path) {
  try {
    (void)readHidDescriptorFile(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "accepted";
}

TEST(HidDescriptorFile, ReadsBinaryCommentedHexAndRecorderLines) {
  const std::vector<std::uint8_t> yoke(std::begin(testdata::kTcaYokeBoeing), std::end(testdata::kTcaYokeBoeing));
  const std::string data = std::string(FIELDCAST_SOURCE_DIR) + "/tests/stick/data/";
  // Binary, as /sys/class/hidraw/hidrawN/device/report_descriptor gives it.
  EXPECT_EQ(readHidDescriptorFile(writeFile("yoke.bin", std::string(yoke.begin(), yoke.end()))), yoke);
  // hid-decode / kernel-source form: 0x prefixes, commas, # and // comments.
  EXPECT_EQ(readHidDescriptorFile(data + "tca_yoke_boeing_commented.txt"), yoke);
  // hid-recorder: the R: line holds the descriptor; # comments, N:, I:, P:, D:, E: lines are not bytes.
  EXPECT_EQ(readHidDescriptorFile(data + "tca_yoke_boeing.hidrec"), yoke);
  // Small forms: /* */ comments, upper case, runs of pairs (xxd -p), a usbhid-dump header line.
  const std::vector<std::uint8_t> mouse{0x05, 0x01, 0x09, 0x02, 0xA1, 0x01, 0xC0};
  EXPECT_EQ(readHidDescriptorFile(writeFile("mouse1.txt",
                                            "/* a mouse\n   (start) */ 0x05,0x01, /* page */ 09 02\r\n"
                                            "A1 01 // collection\nc0\n")),
            mouse);
  EXPECT_EQ(readHidDescriptorFile(writeFile("mouse2.txt", "05010902a101c0\n")), mouse);
  EXPECT_EQ(readHidDescriptorFile(writeFile("mouse3.txt",
                                            "001:003:000:DESCRIPTOR         1712345678.123456\n"
                                            " 05 01 09 02 A1 01 C0\n\n")),
            mouse);
  EXPECT_EQ(readHidDescriptorFile(writeFile("mouse4.txt",
                                            "# 0x05, 0x01, // Usage Page\nR: 7 05 01 09 02 a1 01 c0\n"
                                            "N: Some Mouse\nI: 3 046d c077\n")),
            mouse);
}

TEST(HidDescriptorFile, RefusesWithTheFileAndTheLine) {
  const std::string folder = std::filesystem::temp_directory_path().string();
  EXPECT_EQ(readError(folder), folder + ": is a directory");
  EXPECT_NE(readError("/nonexistent/rdesc").find("/nonexistent/rdesc: cannot read the report descriptor"),
            std::string::npos);
  const std::string empty = writeFile("empty.bin", "");
  EXPECT_EQ(readError(empty), empty + ": empty file");
  const std::string junk = writeFile("junk.txt", "# header\n05 01 09 02\n0x05, 0x01, zz // page\n");
  EXPECT_NE(readError(junk).find(junk + ":3: \"zz\" is not a hex byte"), std::string::npos) << readError(junk);
  const std::string odd = writeFile("odd.txt", "05 0 09\n");
  EXPECT_NE(readError(odd).find(odd + ":1: \"0\" is not a hex byte"), std::string::npos) << readError(odd);
  const std::string wide = writeFile("wide.txt", "0x105\n");
  EXPECT_NE(readError(wide).find(wide + ":1: \"0x105\" is not a hex byte"), std::string::npos) << readError(wide);
  const std::string comments = writeFile("comments.txt", "# nothing\n// here\n\n");
  EXPECT_NE(readError(comments).find(comments + ": no descriptor bytes"), std::string::npos) << readError(comments);
  const std::string unclosed = writeFile("unclosed.txt", "05 01 /* open\n09 02\n");
  EXPECT_NE(readError(unclosed).find(unclosed + ": a /* comment is not closed"), std::string::npos);
  const std::string shortR = writeFile("short.hidrec", "# mouse\nR: 5 05 01 09\n");
  EXPECT_EQ(readError(shortR), shortR + ":2: R: says 5 bytes, the line holds 3");
  const std::string badR = writeFile("bad.hidrec", "R: x 05 01\n");
  EXPECT_NE(readError(badR).find(badR + ":1: R: expected the descriptor length"), std::string::npos);
  const std::string twoR = writeFile("two.hidrec", "R: 2 05 01\nN: a\nR: 2 05 01\n");
  EXPECT_NE(readError(twoR).find(twoR + ":3: a second R: line"), std::string::npos) << readError(twoR);
  const std::string huge = writeFile("huge.bin", std::string((1 << 20) + 1, '\x05'));
  EXPECT_NE(readError(huge).find(huge + ": more than 1048576 bytes"), std::string::npos);
}

TEST(HidrawSource, RefusesADescriptorWithoutInputControls) {
  // The parser reads these as the kernel does (see HidDescriptor.DescriptorsWithoutInputFieldsParse);
  // a source, which exists to deliver input, refuses them when it opens the device.
  const std::vector<std::vector<std::uint8_t>> noInput{
      {0x00},  // one reserved main item: nothing at all
      {0x05, 0x08, 0x09, 0x01, 0xa1, 0x01, 0x09, 0x4b, 0x15, 0x00, 0x25, 0x01,
       0x75, 0x01, 0x95, 0x01, 0x91, 0x02, 0x95, 0x07, 0x91, 0x03, 0xc0},  // one LED: an Output report only
  };
  for (const auto& descriptor : noInput) {
    int fds[2];
    ASSERT_EQ(::socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, fds), 0);
    try {
      HidrawSource source(fds[0], descriptor, "panel");  // closes fds[0] when it throws
      ADD_FAILURE() << "a descriptor of " << descriptor.size() << " bytes without input was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("declares no input controls"), std::string::npos) << e.what();
    }
    ::close(fds[1]);
  }
}

}  // namespace
}  // namespace fieldcast::io
