// fieldcast-stick — the control stick from the command line:
//   list                          input devices (evdev, hidraw, USB HID) and GPIO chips
//   show <source>                 the live ControlState through a profile
//   record <source> <file>        record every input event with its timestamp
//   replay <file>                 print the ControlState of each frame of a recording (CSV)
//   descriptor <file>             parse a HID report descriptor and list its fields: binary (sysfs
//                                 report_descriptor), commented hex (hid-decode, usbhid-dump, 0x05, 0x01,
//                                 …) or a hid-recorder "R: <length> <bytes>" line
// Sources: /dev/input/eventN or a name, hidraw:/dev/hidrawN, usb:vid:pid[:detach], replay:file.
#include <io_bridge/EvdevSource.h>
#include <io_bridge/GpioInput.h>
#include <io_bridge/HidReportDecoder.h>
#include <io_bridge/HidReportDescriptor.h>
#include <io_bridge/HidrawSource.h>
#include <io_bridge/InputSources.h>
#include <io_bridge/StickInput.h>
#include <io_bridge/UsbHidSource.h>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace fieldcast;
using namespace fieldcast::io;

std::atomic<bool> gStop{false};

void onSignal(int) { gStop = true; }

StickProfile profileFrom(const std::string& path) {
  return path.empty() ? StickProfile::generic() : loadStickProfile(path);
}

int list() {
  std::printf("evdev:\n");
  for (const EvdevDeviceInfo& d : listEvdevDevices()) {
    std::printf("  %-20s %04x:%04x %s%s\n", d.path.c_str(), d.vendorId, d.productId, d.name.c_str(),
                d.isJoystick ? "  [joystick]" : "");
  }
  std::printf("hidraw:\n");
  for (const HidrawDeviceInfo& d : listHidrawDevices()) {
    std::printf("  %-20s %04x:%04x %s\n", d.path.c_str(), d.vendorId, d.productId, d.name.c_str());
  }
  std::printf("usb (HID-class interfaces):\n");
  try {
    for (const UsbDeviceInfo& d : listUsbDevices()) {
      std::printf("  usb:%04x:%04x  bus %u device %u interface %d  %s\n", d.vendorId, d.productId, d.bus, d.address,
                  d.interfaceNumber, d.product.c_str());
    }
  } catch (const std::exception& e) {
    std::printf("  (%s)\n", e.what());
  }
  std::printf("gpio:\n");
  for (const std::string& chip : listGpioChips()) std::printf("  %s\n", chip.c_str());
  return 0;
}

void printState(const ControlState& s, bool csv) {
  const char* health = s.health == InputHealth::Live ? "live" : s.health == InputHealth::Holding ? "holding" : "none";
  if (csv) {
    std::printf("%lld,%.9g,%.9g,%.9g,%.9g,%016llx,%d,%s\n", static_cast<long long>(s.time.time_since_epoch().count()),
                s.roll, s.pitch, s.yaw, s.throttle, static_cast<unsigned long long>(s.buttons), s.hat, health);
  } else {
    std::printf("\rroll %+6.3f  pitch %+6.3f  yaw %+6.3f  throttle %5.3f  buttons %016llx  hat %d  %-8s", s.roll,
                s.pitch, s.yaw, s.throttle, static_cast<unsigned long long>(s.buttons), s.hat, health);
    std::fflush(stdout);
  }
}

int run(const std::string& spec, const std::string& profilePath, const std::string& recordPath, double durationS,
        bool show) {
  SystemClock clock;
  StickInputOptions options;
  options.recordPath = recordPath;
  options.reconnect = !isReplaySpec(spec);
  StickInput input(makeSourceFactory(spec, clock), profileFrom(profilePath), options, clock);
  input.start();
  const TimePoint end = clock.now() + fromSeconds(durationS);
  const bool csv = !::isatty(STDOUT_FILENO);
  std::uint64_t shown = 0;
  while (!gStop && (durationS <= 0 || clock.now() < end)) {
    clock.sleepUntil(clock.now() + std::chrono::milliseconds(50));
    const StickInputStats st = input.stats();
    if (show && st.frames != shown) {
      shown = st.frames;
      printState(input.controlsAt(clock.now()), csv);
    }
    if (isReplaySpec(spec) && input.latest().health == InputHealth::Holding) break;
  }
  input.stop();
  const StickInputStats st = input.stats();
  std::printf("\n%llu frames, %llu connects, %llu losses, %llu rejected reports, %llu kernel overruns\n",
              static_cast<unsigned long long>(st.frames), static_cast<unsigned long long>(st.connects),
              static_cast<unsigned long long>(st.losses), static_cast<unsigned long long>(st.rejectedReports),
              static_cast<unsigned long long>(st.droppedBursts));
  return 0;
}

int replay(const std::string& file, const std::string& profilePath, bool realtime) {
  SystemClock clock;
  ReplaySource source(file, realtime ? ReplayPacing::RealTime : ReplayPacing::AsFastAsPossible, clock);
  StickMapper mapper(source.description(), profileFrom(profilePath));
  std::fprintf(stderr, "%s\n", mapper.describeBindings().c_str());
  std::printf("t_ns,roll,pitch,yaw,throttle,buttons,hat,health\n");
  std::vector<InputEvent> events;
  for (;;) {
    events.clear();
    const ReadResult r = source.read(events, std::chrono::seconds(1));
    for (const InputEvent& e : events) {
      if (mapper.apply(e)) printState(mapper.state(), true);
    }
    if (r == ReadResult::End) break;
    if (r == ReadResult::Lost) std::printf("# device lost\n");
  }
  return 0;
}

int descriptor(const std::string& path) {
  const std::vector<std::uint8_t> bytes = readHidDescriptorFile(path);
  HidReportDescriptor d;
  try {
    d = parseHidReportDescriptor(bytes);
  } catch (const HidDescriptorError& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  // The parser reads any descriptor the kernel accepts, output-only ones too; a stick or panel
  // is read through Input reports, so one without an input control is of no use here. This is
  // the check the hidraw and USB sources make when they open a device.
  if (HidInputTranslator(d).controls().empty()) {
    std::size_t other = 0;
    for (const HidField& f : d.fields) other += f.type != HidReportType::Input ? 1 : 0;
    throw std::runtime_error(path + ": the descriptor declares no input field (" + std::to_string(bytes.size()) +
                             " bytes, " + std::to_string(other) +
                             " output or feature fields): a stick or panel reports through Input items");
  }
  static const char* kTypes[] = {"Input", "Output", "Feature"};
  std::printf("%zu bytes, %zu fields, %zu collections, report IDs: %s\n", bytes.size(), d.fields.size(),
              d.collections.size(), d.usesReportIds ? "yes" : "no");
  for (const HidReportInfo& r : d.reports) {
    std::printf("report %u %-7s %zu bytes\n", r.id, kTypes[static_cast<int>(r.type)], r.wireBytes(d.usesReportIds));
  }
  for (const HidField& f : d.fields) {
    std::printf("  %-7s id %3u bit %4u  %2u×%-3u %s %s logical [%d, %d] physical [%d, %d] unit %s  %s%s\n",
                kTypes[static_cast<int>(f.type)], f.reportId, f.bitOffset, f.bitSize, f.count,
                f.isVariable() ? "var" : "arr", f.isConstant() ? "const" : "data ", f.logicalMin, f.logicalMax,
                f.physicalMin, f.physicalMax, describeHidUnit(f.unit, f.unitExponent).c_str(),
                usageName(f.usages.front()).c_str(), f.usages.size() > 1 ? " …" : "");
  }
  return 0;
}

}  // namespace

static int runTool(int argc, char** argv) {
  CLI::App app{"fieldcast-stick: list, show, record and replay control sticks"};
  app.require_subcommand(1);
  std::string source, file, profile;
  double duration = 0;
  bool realtime = false;
  auto* listCmd = app.add_subcommand("list", "List input devices and GPIO chips");
  auto* showCmd = app.add_subcommand("show", "Show the live ControlState of a source");
  showCmd->add_option("source", source, "Device path or name, hidraw:PATH, usb:VID:PID[:detach], replay:FILE")
      ->required();
  showCmd->add_option("--profile", profile, "Stick profile (config/sticks/*.toml); default: generic");
  showCmd->add_option("--duration", duration, "Seconds to run; 0 = until Ctrl-C");
  auto* recordCmd = app.add_subcommand("record", "Record a source's events to a file");
  recordCmd->add_option("source", source, "Device to record")->required();
  recordCmd->add_option("file", file, "Recording to write")->required();
  recordCmd->add_option("--duration", duration, "Seconds to record; 0 = until Ctrl-C");
  recordCmd->add_option("--profile", profile, "Profile for the live display");
  auto* replayCmd = app.add_subcommand("replay", "Print the ControlState of every frame of a recording (CSV)");
  replayCmd->add_option("file", file, "Recording")->required();
  replayCmd->add_option("--profile", profile, "Stick profile; default: generic");
  replayCmd->add_flag("--realtime", realtime, "Pace frames as recorded");
  auto* descriptorCmd = app.add_subcommand(
      "descriptor", "Parse a HID report descriptor file: binary, commented hex, or a hid-recorder R: line");
  descriptorCmd->add_option("file", file, "e.g. /sys/class/hidraw/hidraw0/device/report_descriptor")->required();
  CLI11_PARSE(app, argc, argv);

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  try {
    if (*listCmd) return list();
    if (*showCmd) return run(source, profile, "", duration, true);
    if (*recordCmd) return run(source, profile, file, duration, true);
    if (*replayCmd) return replay(file, profile, realtime);
    if (*descriptorCmd) return descriptor(file);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldcast-stick: %s\n", e.what());
    return 1;
  }
  return 0;
}

int main(int argc, char** argv) {
  try {
    return runTool(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fieldcast-stick: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "fieldcast-stick: unexpected error\n");
  }
  return 1;
}
