// The stick throws. The service runs as a user runs it (its own process, its own clock); the
// stick is a minimal joystick (X and Y, 8 bits each) whose descriptor the run writes. Each throw
// holds the stick centred for 0.35 s — the roll rate is then zero, so the bank stays put — then
// slams it fully to one side for 0.15 s; sides alternate, so the bank stays moderate.
#include "EndToEnd.h"

#include "EmittedFields.h"
#include "HidSocketStick.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <future>
#include <thread>

namespace fieldcast::tools {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// A joystick with two 8-bit axes, X and Y (report: X, Y; no report ID).
constexpr std::uint8_t kDescriptor[] = {0x05, 0x01, 0x09, 0x04, 0xa1, 0x01, 0x15, 0x00, 0x26, 0xff, 0x00,
                                        0x75, 0x08, 0x95, 0x02, 0x09, 0x30, 0x09, 0x31, 0x81, 0x02, 0xc0};
constexpr std::array<std::uint8_t, 2> kCentred{128, 128};
constexpr std::array<std::uint8_t, 2> kRight{255, 128};
constexpr std::array<std::uint8_t, 2> kLeft{0, 128};
constexpr auto kCentredFor = 350ms;
constexpr auto kThrownFor = 150ms;
constexpr double kSearchMs = 300.0;  // a throw not seen within this is counted as missed

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

}  // namespace

EndToEndResult measureStickToField(const EndToEndSpec& spec) {
  EndToEndResult result;
  std::error_code error;
  fs::remove_all(spec.workDir, error);
  fs::create_directories(spec.workDir / "cache", error);
  const fs::path descriptor = spec.workDir / "stick.hid";
  std::ofstream(descriptor, std::ios::binary).write(reinterpret_cast<const char*>(kDescriptor), sizeof kDescriptor);
  const std::string socketPath = (spec.workDir / "stick.sock").string();
  HidSocketStick stick(socketPath, kCentred);
  if (!stick.listening()) {
    result.problem = "cannot listen on " + socketPath;
    return result;
  }

  // A 1 km built-in terrain, the stick flight level at 300 m, the real output raster
  const fs::path config = spec.workDir / "fieldcast.toml";
  const double durationS = 2.5 + spec.throws * std::chrono::duration<double>(kCentredFor + kThrownFor).count() + 1.0;
  std::ofstream(config) << "[terrain]\nsource = \"builtin\"\ncache_dir = \"" << (spec.workDir / "cache").string()
                        << "\"\nbuiltin_size = 512\nmemory_budget_mb = 64\n"
                        << "[output]\nrate = 59.94\nscan = \"interlaced\"\nwidth = " << spec.widthPx
                        << "\nheight = " << spec.heightPx << "\n"
                        << "[motion]\nsource = \"stick\"\nstart = [250.0, 250.0, 300.0, 45.0]\nstart_speed_mps = 80\n"
                        << "[input]\nstick = \"hidsocket:" << socketPath << ":descriptor=" << descriptor.string()
                        << "\"\n"
                        << "[sinks.y4m]\nenabled = true\npath = \"out/video.y4m\"\n"
                        << "[metrics]\nfield_log = \"out/fields.csv\"\n";
  const std::string command = "timeout -s KILL " + std::to_string(static_cast<int>(durationS) + 120) + " " +
                              spec.fieldcastExe + " --config " + config.string() + " --duration " +
                              std::to_string(durationS) + " 2>&1";
  auto service = std::async(std::launch::async, [command] { return runService(command); });

  // Throw once fields flow with the stick connected
  const std::string logPath = (spec.workDir / "out/fields.csv").string();
  const auto deadline = std::chrono::steady_clock::now() + 90s;
  while ((!stick.connected() || readFieldLog(logPath).size() < 60) && std::chrono::steady_clock::now() < deadline &&
         service.wait_for(0s) != std::future_status::ready) {
    std::this_thread::sleep_for(20ms);
  }
  std::vector<std::int64_t> thrownNs;
  for (int k = 0; k < spec.throws && service.wait_for(0s) != std::future_status::ready; ++k) {
    std::this_thread::sleep_for(kCentredFor);
    const std::int64_t t =
        stick.set(k % 2 == 0 ? std::span<const std::uint8_t>(kRight) : std::span<const std::uint8_t>(kLeft));
    if (t != 0) thrownNs.push_back(t);
    std::this_thread::sleep_for(kThrownFor);
    stick.set(kCentred);
  }
  const std::string output = service.get();
  result.throws = static_cast<int>(thrownNs.size());
  const std::vector<LoggedField> fields = readFieldLog(logPath);
  const std::vector<std::string> luma =
      y4mLumaFields((spec.workDir / "out/video.y4m").string(), spec.widthPx, spec.heightPx);
  if (fields.size() < 60 || luma.size() < fields.size() || thrownNs.empty()) {
    result.problem = "the service ran " + std::to_string(fields.size()) + " fields for " +
                     std::to_string(thrownNs.size()) + " throws:\n" + output;
    return result;
  }

  for (const std::int64_t t : thrownNs) {
    // Pose: the first field emitted after the throw whose roll moved from the field before
    std::size_t k = 1;
    while (k < fields.size() && fields[k].emittedNs <= t) ++k;
    while (k < fields.size() && msBetween(t, fields[k].emittedNs) < kSearchMs &&
           std::abs(fields[k].rollDeg - fields[k - 1].rollDeg) < 1e-6) {
      ++k;
    }
    if (k >= fields.size() || msBetween(t, fields[k].emittedNs) >= kSearchMs) continue;
    result.toPoseMs.push_back(msBetween(t, fields[k].emittedNs));
    // Pixels: from that field on, the first whose roll signal (left side's vertical shift minus
    // the right side's, against the field two before: same parity) leaves what it was in the
    // 300 ms before the throw by more than a row and four of its standard deviations
    auto signal = [&](std::uint64_t n) { return rollSignalRows(luma[n - 2], luma[n], spec.widthPx); };
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
