#pragma once
// The rig of the host tests that play the host themselves: TestHost (a CIGI host on a loopback
// socket sending IG Control and the ownship's Entity and Rate Control at 60 Hz, and any View
// Control or View Definition asked for; it reads back the IG's Start of Frames), the flight it
// flies, checks on the Start of Frames, and the fixture that runs the real `fieldcast` service on
// a small built-in terrain and reads its summary and video.
#include "../common/FreePort.h"
#include "../common/MachineStallWatch.h"
#include "../common/RunFieldcast.h"

#include <fieldcast/Pose.h>
#include <ig_core/Georeference.h>
#include <io_bridge/cigi/DatagramDecoder.h>
#include <io_bridge/cigi/MessageBuilder.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fieldcast::host_test {

namespace fs = std::filesystem;
namespace cigi = fieldcast::io::cigi;
using fieldcast::testing::RunResult;
using Steady = std::chrono::steady_clock;
using Bytes = std::vector<std::uint8_t>;

constexpr double kFieldRateHz = 59.94;  // the configured output rate
constexpr double kHostRateHz = 60.0;
constexpr int kOutputWidth = 160, kOutputHeight = 120;
// Missed fields allowed per emitted field. 0 is the design, and what the runs here gave with the
// field thread at SCHED_FIFO; where that is refused (an unprivileged CI runner) the thread has
// ordinary priority, and a 2-core machine busy with other work can deschedule it past a field
// a few times a run (3 of 360 seen): 0.5% keeps such a machine from failing the test.
constexpr double kMissedFieldsAllowed = 0.005;
// Black fields are fields before the first rendered frame; the start-up takes well under a second.
constexpr int kBlackFieldsAllowed = 60;

inline double secondsBetween(Steady::time_point a, Steady::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}
inline Steady::duration seconds(double s) {
  return std::chrono::duration_cast<Steady::duration>(std::chrono::duration<double>(s));
}

using fieldcast::testing::freePort;

// Datagrams the kernel dropped at the 127.0.0.1:`port` socket because its receive buffer was full
// (the last column of /proc/net/udp); nothing when no socket is bound there.
inline std::optional<std::uint64_t> kernelDrops(std::uint16_t port) {
  std::ifstream in("/proc/net/udp");
  std::string line;
  std::getline(in, line);  // header
  char local[32];
  std::snprintf(local, sizeof local, "0100007F:%04X", static_cast<unsigned>(port));
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::vector<std::string> f;
    for (std::string s; fields >> s;) f.push_back(s);
    if (f.size() >= 13 && f[1] == local) return std::stoull(f.back());
  }
  return std::nullopt;
}

// The pid of the `fieldcast` process started with `config`, when it runs.
inline std::optional<int> servicePid(const fs::path& config) {
  for (const fs::directory_entry& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(entry.path() / "cmdline");
    std::vector<std::string> args;
    for (std::string arg; std::getline(in, arg, '\0');) args.push_back(arg);
    if (args.empty() || fs::path(args[0]).filename() != "fieldcast") continue;
    if (std::find(args.begin(), args.end(), config.string()) != args.end()) return std::stoi(name);
  }
  return std::nullopt;
}

// CPU time process `pid` has used so far (user + system), seconds; nothing when it is gone.
inline std::optional<double> cpuSeconds(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  if (!std::getline(in, stat)) return std::nullopt;
  std::istringstream fields(stat.substr(stat.rfind(')') + 2));  // after the command name
  std::vector<std::string> f;
  for (std::string v; fields >> v;) f.push_back(v);
  if (f.size() < 13) return std::nullopt;
  // Fields 14 and 15 of proc(5), counted from the state (field 3).
  return static_cast<double>(std::stoull(f[11]) + std::stoull(f[12])) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

// The host's flight: a level circle of 300 m radius at 60 m/s around the middle of the 1 km
// terrain, 350 m up, heading along the track (world metres: x east, y north, z up).
struct FlightState {
  fieldcast::Pose pose;
  glm::dvec3 velocityMps{0.0};
};
inline FlightState flightAt(double tS) {
  constexpr double kRadiusM = 300.0, kSpeedMps = 60.0;
  const double omega = kSpeedMps / kRadiusM;
  const double a = omega * tS;
  FlightState s;
  s.pose.positionM = {512.0 + kRadiusM * std::cos(a), 512.0 + kRadiusM * std::sin(a), 350.0};
  s.velocityMps = {-kSpeedMps * std::sin(a), kSpeedMps * std::cos(a), 0.0};
  s.pose.headingRad = std::atan2(s.velocityMps.x, s.velocityMps.y);  // clockwise from north
  return s;
}

// One Start of Frame as the test host received it.
struct ReceivedSof {
  Steady::time_point arrival;
  Steady::time_point display;  ///< its field's display time (the IG's clock is CLOCK_MONOTONIC too)
  cigi::StartOfFrame sof;
};

// The instant of a CIGI timestamp (10 µs ticks of CLOCK_MONOTONIC, wrapping at 2³²) near `near`.
inline Steady::time_point unwrapTicks(std::uint32_t ticks, Steady::time_point near) {
  const auto nearTicks = static_cast<std::uint32_t>(near.time_since_epoch().count() / 10'000);
  const auto offset = static_cast<std::int32_t>(ticks - nearTicks);
  return near + std::chrono::microseconds(10 * static_cast<std::int64_t>(offset));
}

// The test's host: one socket for its messages to the IG and the IG's Start of Frames (read by a
// thread of its own), the message builders in the host's byte order, and a count of what it sent.
class TestHost {
 public:
  TestHost(std::uint16_t igPort, cigi::ByteOrder order) : mMessage(order) {
    mFd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in local{};
    local.sin_family = AF_INET;
    local.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(mFd, reinterpret_cast<const sockaddr*>(&local), sizeof local);
    mIg.sin_family = AF_INET;
    mIg.sin_port = htons(igPort);
    mIg.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    mReader = std::thread([this] { readStartOfFrames(); });
  }
  ~TestHost() {
    mStop = true;
    mReader.join();
    ::close(mFd);
  }
  TestHost(const TestHost&) = delete;
  TestHost& operator=(const TestHost&) = delete;

  /// Sends raw bytes to the IG (counted when the system took them).
  void send(std::span<const std::uint8_t> bytes) {
    if (::sendto(mFd, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&mIg), sizeof mIg) >= 0) {
      ++mSent;
    }
  }

  /// One host frame: IG Control (frame number, timestamp), the ownship's Entity Control and its
  /// Rate Control at flight time `flightTimeS`. Returns the message's bytes (valid until the next call).
  std::span<const std::uint8_t> frameMessage(std::uint32_t hostFrame, double hostTimeS, double flightTimeS) {
    cigi::IgControl control;
    control.extrapolationEnabled = true;
    control.databaseNumber = mDatabase;
    control.hostFrameNumber = hostFrame;
    control.timestampValid = true;
    control.timestampTicks = static_cast<std::uint32_t>(std::llround(hostTimeS / 10e-6));
    mMessage.start(control);
    FlightState s = flightAt(mStill ? 0.0 : flightTimeS);
    if (mStill) s.velocityMps = glm::dvec3{0.0};
    const std::optional<fieldcast::core::GeodeticPosition> where = mGeoreference.toGeodetic(s.pose.positionM);
    cigi::EntityControl ownship;
    ownship.entityId = 0;
    ownship.latitudeDegOrXM = where->latitudeDeg;
    ownship.longitudeDegOrYM = where->longitudeDeg;
    ownship.altitudeMOrZM = where->altitudeM;
    ownship.yawDeg = static_cast<float>(s.pose.headingRad * 180.0 / std::numbers::pi + mTurnDeg.load());
    ownship.extrapolationEnabled = true;
    mMessage.add(ownship);
    cigi::RateControl rates;  // world frame: north, east, down
    rates.xRateMps = static_cast<float>(s.velocityMps.y);
    rates.yRateMps = static_cast<float>(s.velocityMps.x);
    rates.zRateMps = static_cast<float>(-s.velocityMps.z);
    mMessage.add(rates);
    if (mView) mMessage.add(*mView);
    if (mDefinition) mMessage.add(*mDefinition);
    return mMessage.bytes();
  }
  void sendFrame(std::uint32_t hostFrame, double hostTimeS, double flightTimeS) {
    send(frameMessage(hostFrame, hostTimeS, flightTimeS));
  }

  /// As a host waits for its IG: IG Control alone, ten times a second, until a Start of Frame
  /// comes back. False when none came within `timeoutS`. Sends only once the IG's socket is
  /// bound, so every datagram counted in sent() reaches it.
  bool waitForIg(double timeoutS) {
    const Steady::time_point giveUp = Steady::now() + seconds(timeoutS);
    while (!kernelDrops(ntohs(mIg.sin_port))) {
      if (Steady::now() > giveUp) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    while (startOfFrameCount() == 0) {
      if (Steady::now() > giveUp) return false;
      mMessage.start(cigi::IgControl{});
      send(mMessage.bytes());
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return true;
  }

  /// What IG Control's database number asks for from the next frame on (0: nothing).
  void requestDatabase(std::int8_t number) { mDatabase = number; }
  /// From the next frame on, the ownship stays where the flight starts, still.
  void holdStill() { mStill = true; }
  /// From the next frame on, the ownship's heading is turned by this much (a step, no rate).
  void turnBy(double degrees) { mTurnDeg = degrees; }
  /// From the next frame on, every frame carries this View Control.
  void sendView(const cigi::ViewControl& view) { mView = view; }
  /// From the next frame on, every frame carries this View Definition.
  void sendDefinition(const cigi::ViewDefinition& definition) { mDefinition = definition; }

  std::uint64_t sent() const noexcept { return mSent; }
  std::size_t startOfFrameCount() const {
    const std::lock_guard lock(mMutex);
    return mReceived.size();
  }
  std::vector<ReceivedSof> startOfFrames() const {
    const std::lock_guard lock(mMutex);
    return mReceived;
  }

 private:
  void readStartOfFrames() {
    cigi::IgDatagramDecoder decoder;
    std::vector<cigi::IgPacket> packets;
    std::vector<std::uint8_t> buffer(cigi::kMaxDatagramBytes);
    while (!mStop.load()) {
      pollfd fd{mFd, POLLIN, 0};
      if (::poll(&fd, 1, 50) <= 0) continue;
      const ssize_t n = ::recv(mFd, buffer.data(), buffer.size(), 0);
      const Steady::time_point arrival = Steady::now();
      if (n <= 0 ||
          !decoder.decode(std::span<const std::uint8_t>(buffer.data(), static_cast<std::size_t>(n)), packets)) {
        continue;
      }
      const auto& sof = std::get<cigi::StartOfFrame>(packets.front());
      const std::lock_guard lock(mMutex);
      mReceived.push_back(ReceivedSof{arrival, unwrapTicks(sof.timestampTicks, arrival), sof});
    }
  }

  int mFd = -1;
  sockaddr_in mIg{};
  cigi::HostMessageBuilder mMessage;
  fieldcast::core::Georeference mGeoreference =
      fieldcast::core::Georeference::tangentPlane();  // [host] origin_deg's default
  std::uint64_t mSent = 0;
  std::int8_t mDatabase = 0;
  bool mStill = false;
  std::atomic<double> mTurnDeg{0.0};
  std::optional<cigi::ViewControl> mView;
  std::optional<cigi::ViewDefinition> mDefinition;
  std::atomic<bool> mStop{false};
  mutable std::mutex mMutex;
  std::vector<ReceivedSof> mReceived;
  std::thread mReader;
};

// Host frames at 60 Hz from `start`: calls `frame(k, tS)` at each frame's instant, for `durationS`.
inline void pace(Steady::time_point start, double durationS, const std::function<void(std::uint32_t, double)>& frame) {
  const auto frames = static_cast<std::uint32_t>(std::llround(durationS * kHostRateHz));
  for (std::uint32_t k = 0; k < frames; ++k) {
    const double tS = k / kHostRateHz;
    std::this_thread::sleep_until(start + seconds(tS));
    frame(k, tS);
  }
}

// Start of Frames of the fields displayed in [from, to).
inline std::vector<ReceivedSof> between(const std::vector<ReceivedSof>& all, Steady::time_point from,
                                        Steady::time_point to) {
  std::vector<ReceivedSof> out;
  for (const ReceivedSof& r : all) {
    if (r.display >= from && r.display < to) out.push_back(r);
  }
  return out;
}

// The most fields between consecutive Start of Frames, by their IG frame numbers: 1 when every
// field had its own.
inline std::uint32_t longestStep(const std::vector<ReceivedSof>& sofs) {
  std::uint32_t longest = 0;
  for (std::size_t k = 1; k < sofs.size(); ++k) {
    longest = std::max(longest, sofs[k].sof.igFrameNumber - sofs[k - 1].sof.igFrameNumber);
  }
  return longest;
}

// The steps other than one field, for failure messages: "+0.512 s: 2 fields ..." from `start`.
inline std::string describeSteps(const std::vector<ReceivedSof>& sofs, Steady::time_point start) {
  std::ostringstream out;
  out.precision(3);
  for (std::size_t k = 1; k < sofs.size(); ++k) {
    const std::uint32_t step = sofs[k].sof.igFrameNumber - sofs[k - 1].sof.igFrameNumber;
    if (step != 1) {
      out << std::fixed << "+" << secondsBetween(start, sofs[k].display) << " s: " << step << " fields (arrived "
          << secondsBetween(sofs[k - 1].arrival, sofs[k].arrival) << " s after the previous); ";
    }
  }
  return out.str();
}

// Fields without a Start of Frame between the first and the last of `sofs`.
inline std::uint64_t fieldsWithoutStartOfFrame(const std::vector<ReceivedSof>& sofs) {
  if (sofs.empty()) return 0;
  return sofs.back().sof.igFrameNumber - sofs.front().sof.igFrameNumber + 1 - sofs.size();
}

// Start of Frames kept coming over `sofs` (the fields displayed in a window starting at `start`):
// every field has its own, except fields the field loop missed (never announced: the summary's
// `fields_missed`) and fields whose announcement found the link's thread late and coalesced with
// the next one into one Start of Frame (README, timing model; the link counts them,
// `fields_coalesced`). The thread runs at SCHED_FIFO below the field thread where the machine
// grants it; where refused it has ordinary priority, and with this 2-core machine's other work at
// full priority (load 6) it was once held off for 0.48 s (28 fields). So the accounting is exact
// and the time bound loose: a link that stops sending (to a silent host, say) fails both.
inline void expectStartOfFramesKeptComing(const std::vector<ReceivedSof>& sofs, const nlohmann::json& summary,
                                          Steady::time_point start) {
  ASSERT_GE(sofs.size(), 2u);
  const auto accountedFor =
      summary["host"]["fields_coalesced"].get<std::uint64_t>() + summary["fields_missed"].get<std::uint64_t>();
  EXPECT_LE(fieldsWithoutStartOfFrame(sofs), accountedFor)
      << "fields without a Start of Frame, neither missed nor coalesced: " << describeSteps(sofs, start);
  EXPECT_LE(longestStep(sofs), 60u) << describeSteps(sofs, start);
}

// The ownship was not held (IG status 0) in the Start of Frames `sofs`. A pose is held when no
// sample was taken for 250 ms; CPU starvation of the link's thread (see above) can make a few
// such fields on a loaded machine, so 5% may be held: a fault the link did not handle holds them all.
inline void expectOwnshipNotHeld(const std::vector<ReceivedSof>& sofs, Steady::time_point start) {
  std::ostringstream held;
  held.precision(3);
  std::size_t count = 0;
  for (const ReceivedSof& r : sofs) {
    if (r.sof.igStatus == 0) continue;
    ++count;
    held << std::fixed << "+" << secondsBetween(start, r.display) << " s: status " << int{r.sof.igStatus} << "; ";
  }
  EXPECT_LE(static_cast<double>(count), std::max(1.0, 0.05 * static_cast<double>(sofs.size())))
      << count << " of " << sofs.size() << " Start of Frames with the ownship held: " << held.str();
}

// The scheduling policy (proc(5) stat field 41: 0 SCHED_OTHER, 1 SCHED_FIFO) of each thread of
// process `pid`, by thread name.
inline std::vector<std::pair<std::string, int>> threadPolicies(int pid) {
  std::vector<std::pair<std::string, int>> out;
  for (const fs::directory_entry& task : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task")) {
    std::string name, stat;
    std::getline(std::ifstream(task.path() / "comm"), name);
    std::getline(std::ifstream(task.path() / "stat"), stat);
    std::istringstream fields(stat.substr(stat.rfind(')') + 2));  // from field 3 on
    std::vector<std::string> f;
    for (std::string v; fields >> v;) f.push_back(v);
    if (f.size() >= 39) out.emplace_back(name, std::stoi(f[38]));
  }
  return out;
}

// ---- The service: the real `fieldcast` on a 1 km built-in terrain, driven by a TestHost --------

class HostServiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    mDir = fs::temp_directory_path() / ("fieldcast_host_test_" + std::to_string(getpid()) + "_" + test->name());
    fs::create_directories(mDir / "cache");
    mPort = freePort();
    // 512 × 512 voxels at 2 m: a 1 km square; a small output rendered at the field rate by one
    // worker (uncapped, the renderer takes both cores of a CI machine); the field thread at
    // SCHED_FIFO as deployed where the machine allows it (refused: logged, and it runs on).
    std::ofstream(mDir / "fieldcast.toml")
        << "[terrain]\nsource = \"builtin\"\ncache_dir = \"" << (mDir / "cache").string()
        << "\"\nbuiltin_size = 512\nmemory_budget_mb = 64\n"
        << "[render]\nthreads = 1\nmax_rate_hz = 60\n"
        << "[output]\nrate = 59.94\nscan = \"progressive\"\nwidth = " << kOutputWidth << "\nheight = " << kOutputHeight
        << "\nformat = \"grey8\"\n"
        << "[motion]\nsource = \"host\"\nstart = [512.0, 512.0, 400.0, 0.0]\n"
        << "[host]\nport = " << mPort << "\nmax_extrapolation_ms = 250\n"
        << "[sinks.y4m]\nenabled = true\npath = \"out/video.y4m\"\n"
        << "[metrics]\nsummary_json = \"out/summary.json\"\n"
        << "[threads]\nrealtime_field_thread = true\n";
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(mDir);
  }

  // Starts the service for `durationS` seconds of video.
  void startService(double durationS, const std::string& moreArgs = "") {
    mDurationS = durationS;
    mStalls = std::make_unique<fieldcast::testing::MachineStallWatch>();
    const std::string config = (mDir / "fieldcast.toml").string();
    mService = std::async(std::launch::async, [config, durationS, moreArgs] {
      return fieldcast::testing::runFieldcast(
          "--config " + config + " --duration " + std::to_string(durationS) + " " + moreArgs, 120);
    });
  }

  // Waits for the service's exit and returns its summary (null when it failed: the test fails).
  nlohmann::json finishService() {
    const RunResult run = mService.get();
    EXPECT_EQ(run.exitCode, 0) << run.output;
    if (run.exitCode != 0) return nullptr;
    return nlohmann::json::parse(std::ifstream(mDir / "out/summary.json"));
  }

  // The video kept going: one field per period of the run, none missed (but the allowance), black
  // fields only before the first rendered frame.
  void expectFieldsContinued(const nlohmann::json& s) {
    const double expected = mDurationS * kFieldRateHz;
    const auto emitted = s["fields_emitted"].get<double>();
    const auto missed = s["fields_missed"].get<double>();
    EXPECT_NEAR(emitted + missed, expected, 3.0) << s.dump();
    // Fields due while the machine itself stood still are the machine's (MachineStallWatch.h)
    const int machine = mStalls ? mStalls->fieldsDueInStalls() : 0;
    EXPECT_LE(missed, std::max(1.0, kMissedFieldsAllowed * emitted) + machine) << s.dump();
    const int black = s["fields_black"].get<int>();
    std::printf(
        "fields: %.0f emitted, %.0f missed (%d due while the machine stalled), %d black; Start of Frames: "
        "%s sent, %s coalesced\n",
        emitted, missed, machine, black, s["host"]["start_of_frames_sent"].dump().c_str(),
        s["host"]["fields_coalesced"].dump().c_str());
    EXPECT_LE(black, kBlackFieldsAllowed) << s.dump();
    // In the video: black fields (uniform, dark) only before the first picture.
    const std::vector<bool> blackFrames = blackFramesOfVideo();
    EXPECT_GE(static_cast<double>(blackFrames.size()), 0.9 * emitted);  // a loaded machine's sink may drop a few
    const auto firstPicture = std::find(blackFrames.begin(), blackFrames.end(), false);
    EXPECT_LE(firstPicture - blackFrames.begin(), kBlackFieldsAllowed);
    EXPECT_EQ(std::count(firstPicture, blackFrames.end(), true), 0) << "a black field after the first picture";
  }

  // The luma planes of the Y4M output's frames, in order (grey8: the frame is its luma).
  std::vector<Bytes> framesOfVideo() const {
    const std::size_t kLuma = static_cast<std::size_t>(kOutputWidth) * kOutputHeight;
    std::ifstream in(mDir / "out/video.y4m", std::ios::binary);
    std::string line;
    std::getline(in, line);
    std::vector<Bytes> frames;
    Bytes luma(kLuma);
    while (std::getline(in, line) &&
           in.read(reinterpret_cast<char*>(luma.data()), static_cast<std::streamsize>(kLuma))) {
      frames.push_back(luma);
    }
    return frames;
  }

  // Per frame of the Y4M output: whether it is black (uniform and dark).
  std::vector<bool> blackFramesOfVideo() const {
    std::vector<bool> black;
    for (const Bytes& luma : framesOfVideo()) {
      const auto [lo, hi] = std::minmax_element(luma.begin(), luma.end());
      black.push_back(*lo == *hi && *hi <= 16);
    }
    return black;
  }

  fs::path mDir;
  std::uint16_t mPort = 0;
  double mDurationS = 0.0;
  std::future<RunResult> mService;
  std::unique_ptr<fieldcast::testing::MachineStallWatch> mStalls;  // beside the service's run
};

// ---- Pictures -------------------------------------------------------------------------------------

// Mean absolute difference of two luma planes, in grey levels.
inline double meanDifference(const Bytes& a, const Bytes& b) {
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += std::abs(int{a[k]} - int{b[k]});
  return sum / static_cast<double>(a.size());
}

// A still ownship's picture changed at video frame `changedAt` (a host's command took effect
// there): steady before it and from 0.5 s after it, and another picture between the two.
inline void expectPictureChangedAt(const std::vector<Bytes>& frames, std::size_t changedAt, const char* what) {
  ASSERT_GT(changedAt, 30u);
  ASSERT_GT(frames.size(), changedAt + 90);
  const double steadyBefore = meanDifference(frames[changedAt - 30], frames[changedAt - 5]);
  const double across = meanDifference(frames[changedAt - 5], frames[changedAt + 60]);
  const double steadyAfter = meanDifference(frames[changedAt + 60], frames[changedAt + 90]);
  std::printf("mean luma difference: %.2f before the %s, %.2f across it, %.2f after\n", steadyBefore, what, across,
              steadyAfter);
  EXPECT_LT(steadyBefore, 2.0);
  EXPECT_LT(steadyAfter, 2.0);
  EXPECT_GT(across, 3.0) << "the picture did not change at the " << what;
}

}  // namespace fieldcast::host_test
