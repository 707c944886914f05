// The step inputs. The service runs as a user runs it (its own process, its own clock) on a 1 km
// built-in terrain. Stick: a minimal joystick (X and Y, 8 bits each) whose descriptor the run
// writes; each throw holds the stick centred for 0.35 s — the roll rate is then zero, so the bank
// stays put — then slams it fully to one side for 0.15 s; sides alternate, so the bank stays
// moderate. Host: the ownship stands still 350 m up, looking 10° down; every 0.5 s its heading
// steps by 10°, alternately there and back.
#include "EndToEnd.h"

#include "EmittedFields.h"
#include "HidSocketStick.h"
#include "StepHost.h"

#include <ig_core/Georeference.h>

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <future>
#include <memory>
#include <thread>

namespace fieldcast::tools {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr double kSearchMs = 300.0;  // a step not seen within this is counted as missed

double msBetween(std::int64_t fromNs, std::int64_t toNs) { return static_cast<double>(toNs - fromNs) * 1e-6; }

std::string runService(const std::string& command) {
  std::string output;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return "cannot start: " + command;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe)) output += buffer.data();
  const int status = ::pclose(pipe);
  if (!(WIFEXITED(status) && WEXITSTATUS(status) == 0)) output += "\n(exit status " + std::to_string(status) + ")";
  return output;
}

/// A UDP port on 127.0.0.1 nobody uses now (bound, read back, released); 0 when none was found.
std::uint16_t freeUdpPort() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof a;
  const bool bound = fd >= 0 && ::bind(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0 &&
                     ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &length) == 0;
  if (fd >= 0) ::close(fd);
  return bound ? ntohs(a.sin_port) : 0;
}

/// One kind of input under test: what the service's configuration says about it, when the service
/// takes it, how a step is made, and how a field shows one.
struct InputUnderTest {
  std::string problem;        ///< why it cannot run (empty when it can)
  std::string configuration;  ///< the [motion] table and the input's own
  std::function<bool(const std::vector<LoggedField>&)> live;
  std::function<std::int64_t(int)> step;  ///< makes step k with the holds around it; its instant (0: not made)
  std::function<bool(const LoggedField& previous, const LoggedField& field)> poseShows;
  /// What the pixels say, from a field two before (same parity) to a field
  std::function<double(const std::string& twoBefore, const std::string& field)> pixelSignal;
  double stepPeriodS = 0.5;
};

// ---- Stick ----------------------------------------------------------------------------------------

// A joystick with two 8-bit axes, X and Y (report: X, Y; no report ID).
constexpr std::uint8_t kDescriptor[] = {0x05, 0x01, 0x09, 0x04, 0xa1, 0x01, 0x15, 0x00, 0x26, 0xff, 0x00,
                                        0x75, 0x08, 0x95, 0x02, 0x09, 0x30, 0x09, 0x31, 0x81, 0x02, 0xc0};
constexpr std::array<std::uint8_t, 2> kCentred{128, 128};
constexpr std::array<std::uint8_t, 2> kRight{255, 128};
constexpr std::array<std::uint8_t, 2> kLeft{0, 128};
constexpr auto kCentredFor = 350ms;
constexpr auto kThrownFor = 150ms;

InputUnderTest stickInput(const EndToEndSpec& spec, std::unique_ptr<HidSocketStick>& stick) {
  InputUnderTest input;
  const fs::path descriptor = spec.workDir / "stick.hid";
  std::ofstream(descriptor, std::ios::binary).write(reinterpret_cast<const char*>(kDescriptor), sizeof kDescriptor);
  const std::string socketPath = (spec.workDir / "stick.sock").string();
  stick = std::make_unique<HidSocketStick>(socketPath, kCentred);
  if (!stick->listening()) input.problem = "cannot listen on " + socketPath;
  input.configuration =
      "[motion]\nsource = \"stick\"\nstart = [250.0, 250.0, 300.0, 45.0]\nstart_speed_mps = 80\n"
      "[input]\nstick = \"hidsocket:" +
      socketPath + ":descriptor=" + descriptor.string() + "\"\n";
  HidSocketStick* device = stick.get();
  input.live = [device](const std::vector<LoggedField>&) { return device->connected(); };
  input.step = [device](int k) {
    std::this_thread::sleep_for(kCentredFor);
    const std::int64_t t =
        device->set(k % 2 == 0 ? std::span<const std::uint8_t>(kRight) : std::span<const std::uint8_t>(kLeft));
    std::this_thread::sleep_for(kThrownFor);
    device->set(kCentred);
    return t;
  };
  input.poseShows = [](const LoggedField& previous, const LoggedField& field) {
    return std::abs(field.rollDeg - previous.rollDeg) >= 1e-6;
  };
  // Roll moves the picture's left and right sides vertically apart; a turn or forward flight does not
  const int width = spec.widthPx;
  input.pixelSignal = [width](const std::string& a, const std::string& b) { return rollSignalRows(a, b, width); };
  input.stepPeriodS = std::chrono::duration<double>(kCentredFor + kThrownFor).count();
  return input;
}

// ---- Host -----------------------------------------------------------------------------------------

constexpr double kHostStepDeg = 10.0;
constexpr auto kHeadingHeldFor = 500ms;

InputUnderTest hostInput(std::unique_ptr<StepHost>& host) {
  InputUnderTest input;
  const std::uint16_t port = freeUdpPort();
  if (port == 0) input.problem = "no free UDP port on 127.0.0.1";
  // The built-in terrain sits on the default tangent plane ([host] origin_deg's default)
  const glm::dvec3 worldM{512.0, 512.0, 350.0};
  const std::optional<core::GeodeticPosition> where = core::Georeference::tangentPlane().toGeodetic(worldM);
  if (!where) input.problem = "the ownship's position has no latitude/longitude";
  HeldOwnship ownship;
  if (where) ownship = {where->latitudeDeg, where->longitudeDeg, where->altitudeM, 45.0, -10.0};
  host = std::make_unique<StepHost>(port, ownship);
  if (!host->open()) input.problem = "cannot open a UDP socket";
  input.configuration =
      "[motion]\nsource = \"host\"\nstart = [512.0, 512.0, 350.0, 45.0]\n[host]\nport = " + std::to_string(port) + "\n";
  input.live = [](const std::vector<LoggedField>& fields) { return fields.back().hasHostSample; };
  StepHost* stepper = host.get();
  input.step = [stepper](int k) {
    std::this_thread::sleep_for(kHeadingHeldFor);
    return stepper->turnTo(k % 2 == 0 ? kHostStepDeg : 0.0);
  };
  input.poseShows = [](const LoggedField& previous, const LoggedField& field) {
    return std::abs(field.headingDeg - previous.headingDeg) >= 1e-6;
  };
  // A still view's fields repeat; a 10° turn of the 60° view moves the picture by a sixth of its width
  input.pixelSignal = [](const std::string& a, const std::string& b) { return meanAbsDifference(a, b); };
  input.stepPeriodS = std::chrono::duration<double>(kHeadingHeldFor).count();
  return input;
}

}  // namespace

const char* name(EndToEndInput input) noexcept { return input == EndToEndInput::Stick ? "stick" : "host"; }

EndToEndResult measureInputToField(const EndToEndSpec& spec) {
  EndToEndResult result;
  result.input = spec.input;
  std::error_code error;
  fs::remove_all(spec.workDir, error);
  fs::create_directories(spec.workDir / "cache", error);
  std::unique_ptr<HidSocketStick> stick;
  std::unique_ptr<StepHost> host;
  InputUnderTest input = spec.input == EndToEndInput::Stick ? stickInput(spec, stick) : hostInput(host);
  if (!input.problem.empty()) {
    result.problem = input.problem;
    return result;
  }

  // A 1 km built-in terrain and the real output raster
  const fs::path config = spec.workDir / "fieldcast.toml";
  const double durationS = 2.5 + spec.steps * input.stepPeriodS + 1.0;
  std::ofstream(config) << "[terrain]\nsource = \"builtin\"\ncache_dir = \"" << (spec.workDir / "cache").string()
                        << "\"\nbuiltin_size = 512\nmemory_budget_mb = 64\n"
                        << "[output]\nrate = 59.94\nscan = \"interlaced\"\nwidth = " << spec.widthPx
                        << "\nheight = " << spec.heightPx << "\n"
                        << input.configuration << "[sinks.y4m]\nenabled = true\npath = \"out/video.y4m\"\n"
                        << "[metrics]\nfield_log = \"out/fields.csv\"\n";
  const std::string command = "timeout -s KILL " + std::to_string(static_cast<int>(durationS) + 120) + " " +
                              spec.fieldcastExe + " --config " + config.string() + " --duration " +
                              std::to_string(durationS) + " 2>&1";
  auto service = std::async(std::launch::async, [command] { return runService(command); });

  // Step once fields flow with the input live
  const std::string logPath = (spec.workDir / "out/fields.csv").string();
  const auto deadline = std::chrono::steady_clock::now() + 90s;
  for (;;) {
    const std::vector<LoggedField> fields = readFieldLog(logPath);
    if ((fields.size() >= 60 && input.live(fields)) || std::chrono::steady_clock::now() > deadline ||
        service.wait_for(0s) == std::future_status::ready) {
      break;
    }
    std::this_thread::sleep_for(20ms);
  }
  std::vector<std::int64_t> stepNs;
  for (int k = 0; k < spec.steps && service.wait_for(0s) != std::future_status::ready; ++k) {
    if (const std::int64_t t = input.step(k); t != 0) stepNs.push_back(t);
  }
  const std::string output = service.get();
  result.steps = static_cast<int>(stepNs.size());
  const std::vector<LoggedField> fields = readFieldLog(logPath);
  const std::vector<std::string> luma =
      y4mLumaFields((spec.workDir / "out/video.y4m").string(), spec.widthPx, spec.heightPx);
  if (fields.size() < 60 || luma.size() < fields.size() || stepNs.empty()) {
    result.problem = "the service ran " + std::to_string(fields.size()) + " fields for " +
                     std::to_string(stepNs.size()) + " steps:\n" + output;
    return result;
  }

  for (const std::int64_t t : stepNs) {
    // Pose: the first field emitted after the step whose pose shows it
    std::size_t k = 1;
    while (k < fields.size() && fields[k].emittedNs <= t) ++k;
    while (k < fields.size() && msBetween(t, fields[k].emittedNs) < kSearchMs &&
           !input.poseShows(fields[k - 1], fields[k])) {
      ++k;
    }
    if (k >= fields.size() || msBetween(t, fields[k].emittedNs) >= kSearchMs) continue;
    result.toPoseMs.push_back(msBetween(t, fields[k].emittedNs));
    // Pixels: from that field on, the first whose signal (against the field two before: same
    // parity) leaves what it was in the 300 ms before the step by more than one (a row, a grey
    // level) and four of its standard deviations
    auto signal = [&](std::uint64_t n) { return input.pixelSignal(luma[n - 2], luma[n]); };
    double sum = 0.0, sum2 = 0.0;
    int count = 0;
    for (const LoggedField& f : fields) {
      const double before = msBetween(f.emittedNs, t);
      if (before > 0.0 && before < kSearchMs && f.number >= 2 && f.number < luma.size()) {
        const double r = signal(f.number);
        sum += r;
        sum2 += r * r;
        ++count;
      }
    }
    const double mean = count > 0 ? sum / count : 0.0;
    const double deviation = count > 1 ? std::sqrt(std::max(0.0, sum2 / count - mean * mean)) : 0.0;
    for (std::size_t j = k; j < fields.size() && msBetween(t, fields[j].emittedNs) < kSearchMs; ++j) {
      const std::uint64_t n = fields[j].number;
      if (n >= 2 && n < luma.size() && std::abs(signal(n) - mean) > std::max(1.0, 4.0 * deviation)) {
        result.toPixelsMs.push_back(msBetween(t, fields[j].emittedNs));
        break;
      }
    }
  }
  fs::remove_all(spec.workDir, error);
  return result;
}

}  // namespace fieldcast::tools
