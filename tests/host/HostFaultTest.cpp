// The faults of the CIGI host link (issue 19 §4), each against the real `fieldcast` service on a
// small built-in terrain: the test plays the host itself — IG Control, Entity Control and Rate
// Control for the ownship at 60 Hz, built with the project's host-side message builders and sent
// over loopback UDP — reads the IG's Start of Frames on its own socket, and then the service's
// summary. Each test injects one fault (a silence, a restart, reordered and duplicated datagrams,
// every malformed kind the decoder counts, the other byte order, a garbage flood) and checks that
// the fields went on and that the counters say exactly what was injected. Last, the host switches
// databases mid-run, which must cost no field either.
#include "../common/FreePort.h"
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
#include <mutex>
#include <numbers>
#include <optional>
#include <random>
#include <span>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

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

double secondsBetween(Steady::time_point a, Steady::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}
Steady::duration seconds(double s) {
  return std::chrono::duration_cast<Steady::duration>(std::chrono::duration<double>(s));
}

using fieldcast::testing::freePort;

// Datagrams the kernel dropped at the 127.0.0.1:`port` socket because its receive buffer was full
// (the last column of /proc/net/udp); nothing when no socket is bound there.
std::optional<std::uint64_t> kernelDrops(std::uint16_t port) {
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
std::optional<int> servicePid(const fs::path& config) {
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
std::optional<double> cpuSeconds(int pid) {
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
FlightState flightAt(double tS) {
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
Steady::time_point unwrapTicks(std::uint32_t ticks, Steady::time_point near) {
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
    ownship.yawDeg = static_cast<float>(s.pose.headingRad * 180.0 / std::numbers::pi);
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
  std::optional<cigi::ViewControl> mView;
  std::optional<cigi::ViewDefinition> mDefinition;
  std::atomic<bool> mStop{false};
  mutable std::mutex mMutex;
  std::vector<ReceivedSof> mReceived;
  std::thread mReader;
};

// Host frames at 60 Hz from `start`: calls `frame(k, tS)` at each frame's instant, for `durationS`.
void pace(Steady::time_point start, double durationS, const std::function<void(std::uint32_t, double)>& frame) {
  const auto frames = static_cast<std::uint32_t>(std::llround(durationS * kHostRateHz));
  for (std::uint32_t k = 0; k < frames; ++k) {
    const double tS = k / kHostRateHz;
    std::this_thread::sleep_until(start + seconds(tS));
    frame(k, tS);
  }
}

// Start of Frames of the fields displayed in [from, to).
std::vector<ReceivedSof> between(const std::vector<ReceivedSof>& all, Steady::time_point from, Steady::time_point to) {
  std::vector<ReceivedSof> out;
  for (const ReceivedSof& r : all) {
    if (r.display >= from && r.display < to) out.push_back(r);
  }
  return out;
}

// The most fields between consecutive Start of Frames, by their IG frame numbers: 1 when every
// field had its own.
std::uint32_t longestStep(const std::vector<ReceivedSof>& sofs) {
  std::uint32_t longest = 0;
  for (std::size_t k = 1; k < sofs.size(); ++k) {
    longest = std::max(longest, sofs[k].sof.igFrameNumber - sofs[k - 1].sof.igFrameNumber);
  }
  return longest;
}

// The steps other than one field, for failure messages: "+0.512 s: 2 fields ..." from `start`.
std::string describeSteps(const std::vector<ReceivedSof>& sofs, Steady::time_point start) {
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
std::uint64_t fieldsWithoutStartOfFrame(const std::vector<ReceivedSof>& sofs) {
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
void expectStartOfFramesKeptComing(const std::vector<ReceivedSof>& sofs, const nlohmann::json& summary,
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
void expectOwnshipNotHeld(const std::vector<ReceivedSof>& sofs, Steady::time_point start) {
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
std::vector<std::pair<std::string, int>> threadPolicies(int pid) {
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

// ---- Malformed datagrams: one kind per reason the decoder counts ----------------------------

// A good host message (IG Control + the ownship's Entity Control), the base of the malformed ones.
Bytes goodMessage() {
  cigi::HostMessageBuilder message;
  cigi::IgControl control;
  control.hostFrameNumber = 7;
  message.start(control);
  message.add(cigi::EntityControl{});
  const auto bytes = message.bytes();
  return Bytes(bytes.begin(), bytes.end());
}

// A datagram the decoder rejects for `reason`; `variant` picks among the ways to get there. The
// switch has no default, so a new reason is a compiler warning here, and an empty answer fails
// the test below: a new reason cannot be forgotten.
std::optional<Bytes> malformedDatagram(cigi::RejectReason reason, int variant) {
  constexpr std::size_t kEntityAt = cigi::IgControl::kSize;  // the Entity Control's offset
  Bytes d = goodMessage();
  switch (reason) {
    case cigi::RejectReason::TooShort:
      return variant % 2 == 0 ? Bytes{cigi::IgControl::kOpcode} : Bytes{};  // one byte, or an empty datagram
    case cigi::RejectReason::NoLeadingControl: return Bytes(d.begin() + kEntityAt, d.end());  // Entity Control first
    case cigi::RejectReason::WrongMajorVersion: d[2] = variant % 2 == 0 ? 2 : 4; return d;
    case cigi::RejectReason::UnsupportedMinorVersion:
      if (variant % 2 == 0) {
        d[4] = static_cast<std::uint8_t>((d[4] & 0x0F) | (1 << 4));  // CIGI 3.1
        return d;
      }
      d.resize(16);  // a CIGI 3.0 IG Control: 16 bytes
      d[1] = 16;
      return d;
    case cigi::RejectReason::BadByteSwapMagic:
      d[6] = 0x12;
      d[7] = 0x34;
      return d;
    case cigi::RejectReason::ZeroPacketSize:
      d[variant % 2 == 0 ? kEntityAt + 1 : 1] = 0;  // the Entity Control's size, or the IG Control's
      return d;
    case cigi::RejectReason::PacketPastEnd:
      if (variant % 2 == 0) {
        d.resize(d.size() - 8);  // the Entity Control runs past the end
      } else {
        d.push_back(cigi::EntityControl::kOpcode);  // a lone byte: half a packet header
      }
      return d;
    case cigi::RejectReason::WrongPacketSize:
      d[kEntityAt + 1] = 40;  // an Entity Control is 48 bytes
      return d;
  }
  return std::nullopt;
}

// ---- The service ------------------------------------------------------------------------------

class HostFault : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    mDir = fs::temp_directory_path() / ("fieldcast_host_fault_" + std::to_string(getpid()) + "_" + test->name());
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
    EXPECT_LE(missed, std::max(1.0, kMissedFieldsAllowed * emitted)) << s.dump();
    const int black = s["fields_black"].get<int>();
    std::printf("fields: %.0f emitted, %.0f missed, %d black; Start of Frames: %s sent, %s coalesced\n", emitted,
                missed, black, s["host"]["start_of_frames_sent"].dump().c_str(),
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
};

// ---- The faults -------------------------------------------------------------------------------

TEST_F(HostFault, SilentHostIsHeldThenResumesWithoutAGap) {
  startService(6.0);
  TestHost host(mPort, cigi::nativeByteOrder());
  ASSERT_TRUE(host.waitForIg(60.0)) << "no Start of Frame from the service";
  const std::uint64_t waitMessages = host.sent();
  // Host time 0–1.5 s flying, silent for 2 s, then flying again to 5 s.
  constexpr double kSilentFromS = 1.5, kSilentForS = 2.0, kFlightS = 5.0;
  std::uint32_t lastFrameBefore = 0, firstFrameAfter = 0, framesSent = 0;
  Steady::time_point resumeSent{};
  const Steady::time_point start = Steady::now();
  pace(start, kFlightS, [&](std::uint32_t k, double tS) {
    if (tS >= kSilentFromS && tS < kSilentFromS + kSilentForS) return;
    if (tS >= kSilentFromS && resumeSent == Steady::time_point{}) {
      resumeSent = Steady::now();
      firstFrameAfter = k;
    }
    host.sendFrame(k, tS, tS);
    ++framesSent;
    if (tS < kSilentFromS) lastFrameBefore = k;
  });
  const nlohmann::json s = finishService();
  ASSERT_FALSE(s.is_null());
  expectFieldsContinued(s);

  // The host's instants on the IG's clock: each pose is placed where its frame was due (the
  // clock estimate takes the earliest arrivals, and the pacing is never early).
  const Steady::time_point lastBefore = start + seconds(lastFrameBefore / kHostRateHz);
  const Steady::time_point firstAfter = start + seconds(firstFrameAfter / kHostRateHz);
  const Steady::time_point end = start + seconds(kFlightS);
  const std::vector<ReceivedSof> all = host.startOfFrames();
  // Start of Frames kept coming, one per field, the silence included.
  expectStartOfFramesKeptComing(between(all, start, end), s, start);
  expectStartOfFramesKeptComing(between(all, lastBefore, firstAfter), s, start);
  // Within the extrapolation bound (250 ms) the status is normal; past it "ownship held" (1)
  // until the host is back, with the last host frame heard before the silence echoed.
  expectOwnshipNotHeld(between(all, lastBefore, lastBefore + seconds(0.2)), start);
  std::size_t heldCount = 0, notHeld = 0;
  std::string firstNotHeld;
  for (const ReceivedSof& r : between(all, lastBefore + seconds(0.3), firstAfter)) {
    if (r.arrival >= resumeSent) continue;  // made after the host was back
    ++heldCount;
    if (r.sof.igStatus == 1 && r.sof.lastHostFrameNumber == lastFrameBefore) continue;
    if (notHeld++ == 0) {
      firstNotHeld = std::to_string(secondsBetween(lastBefore, r.display)) + " s into the silence: status " +
                     std::to_string(r.sof.igStatus) + ", last host frame " + std::to_string(r.sof.lastHostFrameNumber);
    }
  }
  EXPECT_EQ(notHeld, 0u) << "of " << heldCount << " Start of Frames past the bound; the first: " << firstNotHeld;
  EXPECT_GE(heldCount, 20u);  // about 100 at one per field
  // Back to normal once the host resumed, echoing its new frames.
  const std::vector<ReceivedSof> resumed = between(all, firstAfter + seconds(0.1), end);
  EXPECT_GE(resumed.size(), 20u);  // 84 at one per field
  expectOwnshipNotHeld(resumed, start);
  EXPECT_EQ(std::count_if(resumed.begin(), resumed.end(),
                          [&](const ReceivedSof& r) { return r.sof.lastHostFrameNumber < firstFrameAfter; }),
            0)
      << "Start of Frames echoing a host frame from before the silence after the host resumed";
  // The resume is seamless on the wire: the Start of Frames go on through it.
  expectStartOfFramesKeptComing(between(all, firstAfter - seconds(0.3), firstAfter + seconds(0.3)), s, start);

  // The link saw one host throughout: every datagram accepted, every sample taken, no restart
  // (its clock and frame numbers went on).
  const nlohmann::json& link = s["host"];
  EXPECT_EQ(link["datagrams_accepted"].get<std::uint64_t>(), waitMessages + framesSent) << link.dump();
  EXPECT_EQ(link["ownship_samples"].get<std::uint32_t>(), framesSent) << link.dump();
  EXPECT_EQ(link["host_restarts"].get<int>(), 0) << link.dump();
  EXPECT_EQ(link["samples_reordered"].get<int>(), 0) << link.dump();
}

TEST_F(HostFault, RestartedHostIsFollowedAtOnce) {
  startService(6.0);
  TestHost host(mPort, cigi::nativeByteOrder());
  ASSERT_TRUE(host.waitForIg(60.0)) << "no Start of Frame from the service";
  // 2.5 s of a host that has been running for a while (frame 5000 on, host clock at 1000 s),
  // then the host restarts: frame numbers and timestamps from 0, the same flight going on.
  constexpr double kRestartAtS = 2.5;
  constexpr std::uint32_t kFramesBefore = 150;  // 2.5 s at 60 Hz
  Steady::time_point restarted{};
  std::uint32_t framesSent = 0, lastFrame = 0;
  const Steady::time_point start = Steady::now();
  pace(start, 5.0, [&](std::uint32_t k, double tS) {
    if (tS < kRestartAtS) {
      host.sendFrame(5000 + k, 1000.0 + tS, tS);
    } else {
      if (restarted == Steady::time_point{}) restarted = Steady::now();
      lastFrame = k - kFramesBefore;
      host.sendFrame(lastFrame, tS - kRestartAtS, tS);
    }
    ++framesSent;
  });
  const Steady::time_point end = Steady::now();
  const nlohmann::json s = finishService();
  ASSERT_FALSE(s.is_null());
  expectFieldsContinued(s);

  const nlohmann::json& link = s["host"];
  EXPECT_EQ(link["host_restarts"].get<int>(), 1) << link.dump();
  // Every sample after the restart was taken (none dropped as older than the old track's).
  EXPECT_EQ(link["ownship_samples"].get<std::uint32_t>(), framesSent) << link.dump();
  EXPECT_EQ(link["samples_reordered"].get<int>(), 0) << link.dump();
  EXPECT_EQ(link["samples_duplicated"].get<int>(), 0) << link.dump();
  EXPECT_EQ(link["last_host_frame"].get<std::uint32_t>(), lastFrame) << link.dump();
  // The new track is followed at once: never held, and the new frame numbers echoed.
  const std::vector<ReceivedSof> all = host.startOfFrames();
  expectStartOfFramesKeptComing(between(all, start, end), s, start);
  expectOwnshipNotHeld(between(all, start + seconds(0.1), end), start);
  const std::vector<ReceivedSof> after = between(all, restarted + seconds(0.1), end);
  ASSERT_FALSE(after.empty());
  EXPECT_EQ(std::count_if(after.begin(), after.end(),
                          [&](const ReceivedSof& r) { return r.sof.lastHostFrameNumber > lastFrame; }),
            0)
      << "Start of Frames echoing the old host's frame numbers after the restart";
}

TEST_F(HostFault, ReorderedAndDuplicatedDatagramsAreDroppedAndCounted) {
  startService(5.0);
  TestHost host(mPort, cigi::nativeByteOrder());
  ASSERT_TRUE(host.waitForIg(60.0)) << "no Start of Frame from the service";
  const std::uint64_t waitMessages = host.sent();
  // 240 host frames: every 16th sent twice (a duplicate), and every 16th pair (another phase)
  // swapped, its earlier frame arriving after the later one (reordered). HostMotion drops a pose
  // at the newest's host time as a duplicate and an older one as reordered: the counts are exact.
  constexpr std::uint32_t kFrames = 240;
  std::uint32_t duplicated = 0, reordered = 0;
  Bytes held;  // the earlier frame of a swapped pair, sent after the later one
  const Steady::time_point start = Steady::now();
  pace(start, kFrames / kHostRateHz, [&](std::uint32_t k, double tS) {
    const std::span<const std::uint8_t> message = host.frameMessage(k, tS, tS);
    if (k % 16 == 9 && k + 1 < kFrames) {
      held.assign(message.begin(), message.end());
      return;
    }
    host.send(message);
    if (!held.empty()) {
      host.send(held);
      held.clear();
      ++reordered;
    }
    if (k % 16 == 3) {
      host.send(message);
      ++duplicated;
    }
  });
  const nlohmann::json s = finishService();
  ASSERT_FALSE(s.is_null());
  expectFieldsContinued(s);

  const nlohmann::json& link = s["host"];
  ASSERT_GT(duplicated, 10u);
  ASSERT_GT(reordered, 10u);
  EXPECT_EQ(link["datagrams_accepted"].get<std::uint64_t>(), waitMessages + kFrames + duplicated) << link.dump();
  EXPECT_EQ(link["samples_duplicated"].get<std::uint32_t>(), duplicated) << link.dump();
  EXPECT_EQ(link["samples_reordered"].get<std::uint32_t>(), reordered) << link.dump();
  EXPECT_EQ(link["ownship_samples"].get<std::uint32_t>(), kFrames - reordered) << link.dump();
  EXPECT_EQ(link["host_restarts"].get<int>(), 0) << link.dump();
}

TEST_F(HostFault, EveryMalformedKindIsRejectedAndCountedByReason) {
  // A different count per reason, so counts landing under the wrong reason show too.
  std::vector<Bytes> malformed;
  nlohmann::json expected = nlohmann::json::object();
  cigi::HostDatagramDecoder check;
  std::vector<cigi::HostPacket> packets;
  for (std::size_t k = 0; k < cigi::kRejectReasonCount; ++k) {
    const auto reason = static_cast<cigi::RejectReason>(k);
    const std::string name(cigi::toString(reason));
    ASSERT_NE(name, "unknown reason") << "RejectReason " << k << " has no name";
    const int count = static_cast<int>(k) + 3;
    for (int variant = 0; variant < count; ++variant) {
      const std::optional<Bytes> d = malformedDatagram(reason, variant);
      ASSERT_TRUE(d.has_value()) << "no malformed datagram for '" << name << "': add one to malformedDatagram()";
      // The datagram is what it claims to be: the project's decoder rejects it for this reason.
      ASSERT_EQ(check.decode(*d, packets).rejected, reason) << name << ", variant " << variant;
      malformed.push_back(*d);
    }
    expected[name] = count;
  }
  std::shuffle(malformed.begin(), malformed.end(), std::mt19937(19));

  startService(5.0);
  TestHost host(mPort, cigi::nativeByteOrder());
  ASSERT_TRUE(host.waitForIg(60.0)) << "no Start of Frame from the service";
  const std::uint64_t waitMessages = host.sent();
  // 3.5 s of good host frames, one malformed datagram after every third of them.
  std::uint32_t framesSent = 0;
  std::size_t next = 0;
  pace(Steady::now(), 3.5, [&](std::uint32_t k, double tS) {
    host.sendFrame(k, tS, tS);
    ++framesSent;
    if (k % 3 == 1 && next < malformed.size()) host.send(malformed[next++]);
  });
  ASSERT_EQ(next, malformed.size()) << "the flight was too short to send every malformed datagram";
  const nlohmann::json s = finishService();
  ASSERT_FALSE(s.is_null());
  expectFieldsContinued(s);

  const nlohmann::json& link = s["host"];
  EXPECT_EQ(link["rejected_by_reason"], expected) << link.dump();
  EXPECT_EQ(link["datagrams_rejected"].get<std::size_t>(), malformed.size()) << link.dump();
  // The good datagrams between them: every one accepted, every pose taken.
  EXPECT_EQ(link["datagrams_accepted"].get<std::uint64_t>(), waitMessages + framesSent) << link.dump();
  EXPECT_EQ(link["ownship_samples"].get<std::uint32_t>(), framesSent) << link.dump();
}

TEST_F(HostFault, ByteSwappedHostIsSwappedOnReceipt) {
  startService(5.0);
  // The whole run in the other byte order, the wait for the IG included.
  TestHost host(mPort, cigi::swappedByteOrder());
  ASSERT_TRUE(host.waitForIg(60.0)) << "no Start of Frame from the service";
  constexpr std::uint32_t kFrames = 240;
  const Steady::time_point start = Steady::now();
  pace(start, kFrames / kHostRateHz, [&](std::uint32_t k, double tS) { host.sendFrame(k, 500.0 + tS, tS); });
  const Steady::time_point end = Steady::now();
  const nlohmann::json s = finishService();
  ASSERT_FALSE(s.is_null());
  expectFieldsContinued(s);

  const nlohmann::json& link = s["host"];
  EXPECT_EQ(link["datagrams_byte_swapped"].get<std::uint64_t>(), host.sent()) << link.dump();
  EXPECT_EQ(link["datagrams_accepted"].get<std::uint64_t>(), host.sent()) << link.dump();
  EXPECT_EQ(link["datagrams_rejected"].get<int>(), 0) << link.dump();
  // The swapped poses, frame numbers and timestamps read right: every pose taken on one track.
  EXPECT_EQ(link["ownship_samples"].get<std::uint32_t>(), kFrames) << link.dump();
  EXPECT_EQ(link["host_restarts"].get<int>(), 0) << link.dump();
  EXPECT_EQ(link["samples_reordered"].get<int>(), 0) << link.dump();
  EXPECT_EQ(link["last_host_frame"].get<std::uint32_t>(), kFrames - 1) << link.dump();
  const std::vector<ReceivedSof> all = host.startOfFrames();
  expectOwnshipNotHeld(between(all, start + seconds(0.1), end), start);
  const std::vector<ReceivedSof> flight = between(all, start + seconds(0.1), end);
  ASSERT_FALSE(flight.empty());
  const auto echoed = std::max_element(flight.begin(), flight.end(), [](const ReceivedSof& a, const ReceivedSof& b) {
    return a.sof.lastHostFrameNumber < b.sof.lastHostFrameNumber;
  });
  EXPECT_LT(echoed->sof.lastHostFrameNumber, kFrames) << "a host frame number read in the wrong byte order";
}

TEST_F(HostFault, GarbageFloodCostsNoFieldAndNoPose) {
  startService(5.5);
  TestHost host(mPort, cigi::nativeByteOrder());
  ASSERT_TRUE(host.waitForIg(60.0)) << "no Start of Frame from the service";
  const std::uint64_t waitMessages = host.sent();
  const std::uint64_t dropsBefore = kernelDrops(mPort).value_or(0);

  // 20,000 datagrams/s of random bytes (1–200 of them) from another socket, for 2 s in the middle
  // of a 4.5 s flight: 20 every millisecond.
  constexpr double kFloodFromS = 1.0, kFloodForS = 2.0;
  constexpr int kPerMillisecond = 20;
  std::atomic<std::uint64_t> garbageSent{0};
  const Steady::time_point start = Steady::now();
  std::thread flood([&] {
    TestHost garbage(mPort, cigi::nativeByteOrder());
    std::mt19937 random(2026);
    std::uniform_int_distribution<int> length(1, 200), byte(0, 255);
    Bytes d;
    const Steady::time_point floodStart = start + seconds(kFloodFromS);
    const auto milliseconds = static_cast<int>(kFloodForS * 1000);
    for (int ms = 0; ms < milliseconds; ++ms) {
      std::this_thread::sleep_until(floodStart + std::chrono::milliseconds(ms));
      for (int k = 0; k < kPerMillisecond; ++k) {
        d.resize(static_cast<std::size_t>(length(random)));
        for (std::uint8_t& b : d) b = static_cast<std::uint8_t>(byte(random));
        garbage.send(d);
      }
    }
    garbageSent = garbage.sent();
  });
  // The service's CPU time at the flight's start, the flood's start and end, and the flight's end.
  const std::optional<int> pid = servicePid(mDir / "fieldcast.toml");
  std::array<std::optional<double>, 4> cpu;
  std::uint32_t framesSent = 0;
  pace(start, 4.5, [&](std::uint32_t k, double tS) {
    if (pid && k == 0) cpu[0] = cpuSeconds(*pid);
    if (pid && k == 60) cpu[1] = cpuSeconds(*pid);   // 1.0 s: the flood starts
    if (pid && k == 180) cpu[2] = cpuSeconds(*pid);  // 3.0 s: it ends
    host.sendFrame(k, tS, tS);
    ++framesSent;
  });
  if (pid) cpu[3] = cpuSeconds(*pid);
  const Steady::time_point flightEnd = Steady::now();
  flood.join();
  const Steady::time_point end = Steady::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the link drains its socket
  const std::optional<std::uint64_t> dropsAfter = kernelDrops(mPort);
  const nlohmann::json s = finishService();
  ASSERT_FALSE(s.is_null());
  expectFieldsContinued(s);

  const nlohmann::json& link = s["host"];
  const auto received = link["datagrams_received"].get<std::uint64_t>();
  const auto accepted = link["datagrams_accepted"].get<std::uint64_t>();
  const auto rejected = link["datagrams_rejected"].get<std::uint64_t>();
  const std::uint64_t sent = waitMessages + framesSent + garbageSent;
  EXPECT_EQ(garbageSent.load(), static_cast<std::uint64_t>(kFloodForS * 1000 * kPerMillisecond));
  // Loopback UDP loses datagrams only where the receiver's socket buffer overflows: the kernel
  // counts those (/proc/net/udp), so what the link read is what was sent less what was dropped.
  // On an idle machine nothing is dropped; with the 2 cores busy with other work about 18% were.
  const std::uint64_t drops = dropsAfter.value_or(dropsBefore) - dropsBefore;
  // The flood's cost: the service's CPU time during it less that of the same time without it
  // (the rate before and after). About 4 µs per datagram (0.16 s) on an idle machine, up to
  // 0.32 s with the cores shared; the bound, 0.35 of a core (17 µs per datagram), fails a link
  // that spends 20 µs on each.
  ASSERT_TRUE(pid.has_value()) << "the service's process was not found";
  ASSERT_TRUE(cpu[0] && cpu[1] && cpu[2] && cpu[3]) << "no CPU time from /proc/" << *pid << "/stat";
  const double quietRate = (*cpu[1] - *cpu[0] + *cpu[3] - *cpu[2]) / (secondsBetween(start, flightEnd) - kFloodForS);
  const double floodCpuS = *cpu[2] - *cpu[1] - quietRate * kFloodForS;
  EXPECT_LE(floodCpuS, 0.35 * kFloodForS);
  EXPECT_LE(received, sent);
  if (dropsAfter) {
    EXPECT_EQ(received + drops, sent) << link.dump();
  }
  std::printf(
      "garbage flood: %llu garbage datagrams sent, %llu datagrams read by the link, %llu dropped by the "
      "kernel; service CPU %.3f s/s without the flood, %.3f s more during its %.1f s\n",
      static_cast<unsigned long long>(garbageSent.load()), static_cast<unsigned long long>(received),
      static_cast<unsigned long long>(drops), quietRate, floodCpuS, kFloodForS);
  // Every garbage datagram read was rejected (random bytes are not a CIGI message), every good one
  // accepted and its pose taken, but for those the kernel dropped.
  const std::uint64_t good = waitMessages + framesSent;
  EXPECT_EQ(rejected + accepted, received) << link.dump();
  EXPECT_LE(accepted, good) << link.dump();
  EXPECT_GE(accepted + drops, good) << link.dump();
  EXPECT_GE(rejected + drops, garbageSent.load()) << link.dump();
  EXPECT_EQ(link["ownship_samples"].get<std::uint64_t>(), accepted - waitMessages) << link.dump();
  EXPECT_GE(static_cast<double>(link["ownship_samples"].get<std::uint32_t>()), 0.5 * framesSent) << link.dump();
  // The Start of Frames went on through the flood, and the ownship never fell back to held.
  const std::vector<ReceivedSof> all = host.startOfFrames();
  expectStartOfFramesKeptComing(between(all, start, end), s, start);
  expectOwnshipNotHeld(between(all, start + seconds(0.1), end), start);
}

}  // namespace

// ---- A database switch mid-run ------------------------------------------------------------------

// Mean absolute difference of two luma planes, in grey levels.
double meanDifference(const Bytes& a, const Bytes& b) {
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += std::abs(int{a[k]} - int{b[k]});
  return sum / static_cast<double>(a.size());
}

// A still ownship's picture changed at video frame `changedAt` (a host's command took effect
// there): steady before it and from 0.5 s after it, and another picture between the two.
void expectPictureChangedAt(const std::vector<Bytes>& frames, std::size_t changedAt, const char* what) {
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

// IG Control asks for database 2 (the built-in terrain of another seed) while the ownship holds
// still over the middle of the terrain: Start of Frame says 1, then −2 while it loads (a fresh
// built-in terrain is generated: longer than a field), then 2; the video goes on without a
// missed or black field, and the picture, steady before, is another terrain after.
class HostDatabaseSwitch : public HostFault {
 protected:
  void SetUp() override {
    HostFault::SetUp();
    std::ofstream(mDir / "fieldcast.toml", std::ios::app)
        << "[[host.database]]\nnumber = 2\nbuiltin_size = 512\nbuiltin_seed = 7\nmemory_budget_mb = 64\n"
        << "cache_dir = \"" << (mDir / "cache").string() << "\"\n";
  }
};

TEST_F(HostDatabaseSwitch, TheHostSwitchesDatabasesBetweenFieldsWithoutLosingOne) {
  startService(7.0);
  TestHost host(mPort, cigi::nativeByteOrder());
  ASSERT_TRUE(host.waitForIg(60.0)) << "no Start of Frame from the service";
  host.holdStill();
  constexpr double kSwitchAtS = 2.5, kFlightS = 6.0;
  const Steady::time_point start = Steady::now();
  pace(start, kFlightS, [&](std::uint32_t k, double tS) {
    if (tS >= kSwitchAtS) host.requestDatabase(2);
    host.sendFrame(k, tS, tS);
  });
  const nlohmann::json s = finishService();
  ASSERT_FALSE(s.is_null());
  expectFieldsContinued(s);
  EXPECT_EQ(s["host"]["database_number"], 2) << s.dump();
  EXPECT_EQ(s["host"]["database_switches"], 1) << s.dump();
  EXPECT_EQ(s["host"]["database_load_failures"], 0) << s.dump();

  // Start of Frame's database number: 1, then −2, then 2, in that order and nothing else.
  const std::vector<ReceivedSof> all = host.startOfFrames();
  expectStartOfFramesKeptComing(between(all, start, start + seconds(kFlightS)), s, start);
  std::vector<std::pair<int, std::uint32_t>> runs;  // (database number, first IG frame) per run
  for (const ReceivedSof& r : all) {
    if (runs.empty() || runs.back().first != r.sof.databaseNumber) {
      runs.emplace_back(r.sof.databaseNumber, r.sof.igFrameNumber);
    }
  }
  ASSERT_EQ(runs.size(), 3u) << "expected runs of 1, −2, 2";
  EXPECT_EQ(runs[0].first, 1);
  EXPECT_EQ(runs[1].first, -2);
  EXPECT_EQ(runs[2].first, 2);
  const std::uint32_t loadingFrom = runs[1].second, switchedAt = runs[2].second;
  std::printf("database 2: loading from field %u, switched at field %u (%.2f s later)\n", loadingFrom, switchedAt,
              (switchedAt - loadingFrom) / kFieldRateHz);

  // The picture: the same before the request (a still ownship), another terrain 0.5 s after the
  // switch. The video's frame k is field k when no field was missed; a missed field shifts the
  // index by one frame of the same still picture.
  expectPictureChangedAt(framesOfVideo(), switchedAt, "database switch");
}

// ---- A view moved by the host -------------------------------------------------------------------

// View Control turns the eye 180° on a still ownship mid-run: every field after it (the per-field
// record) looks the other way, the picture changes and the video goes on without a missed field.
TEST_F(HostFault, ViewControlTurnsTheEyeWithoutLosingAField) {
  startService(6.0, "--field-log " + (mDir / "out/fields.csv").string());
  TestHost host(mPort, cigi::nativeByteOrder());
  ASSERT_TRUE(host.waitForIg(60.0)) << "no Start of Frame from the service";
  host.holdStill();
  constexpr double kTurnAtS = 2.0, kFlightS = 5.0;
  cigi::ViewControl turn;
  turn.yawEnabled = true;
  turn.yawDeg = 180.0f;
  const Steady::time_point start = Steady::now();
  pace(start, kFlightS, [&](std::uint32_t k, double tS) {
    if (tS >= kTurnAtS) host.sendView(turn);
    host.sendFrame(k, tS, tS);
  });
  const nlohmann::json s = finishService();
  ASSERT_FALSE(s.is_null());
  expectFieldsContinued(s);
  EXPECT_GE(s["host"]["view_controls"].get<int>(), 60) << s.dump();

  // The fields' headings: the ownship's before, the ownship's + 180° after (the record is the eye's).
  const double ownshipDeg = flightAt(0.0).pose.headingRad * 180.0 / std::numbers::pi;
  std::ifstream log(mDir / "out/fields.csv");
  std::string line;
  std::getline(log, line);  // header
  std::vector<double> headings;
  while (std::getline(log, line)) {
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    ASSERT_GE(cells.size(), 7u) << line;
    headings.push_back(std::stod(cells[6]));  // heading_deg
  }
  const auto offFromOwnship = [&](double headingDeg) {
    return std::abs(std::remainder(headingDeg - ownshipDeg, 360.0));
  };
  std::size_t before = 0, after = 0, between = 0, turnedAt = 0;
  for (std::size_t k = 0; k < headings.size(); ++k) {
    const double off = offFromOwnship(headings[k]);
    if (off < 0.5) {
      ++before;
    } else if (off > 179.5) {
      if (after++ == 0) turnedAt = k;
    } else {
      ++between;
    }
  }
  std::printf("fields looking along the ownship: %zu, the other way: %zu, neither: %zu\n", before, after, between);
  EXPECT_GE(after, 120u);  // about 3 s of fields
  EXPECT_EQ(between, 0u) << "a field whose eye looks neither along the ownship nor against it";

  // The picture: the log's lines and the video's frames are the emitted fields, in order.
  expectPictureChangedAt(framesOfVideo(), turnedAt, "turn");
}

// View Definition narrows the frustum to ±10° × ±7.5° mid-run (a zoom): the video goes on without
// a missed or black field, and the picture, steady before and after, changes.
TEST_F(HostFault, ViewDefinitionZoomsWithoutLosingAField) {
  startService(6.0);
  TestHost host(mPort, cigi::nativeByteOrder());
  ASSERT_TRUE(host.waitForIg(60.0)) << "no Start of Frame from the service";
  host.holdStill();
  constexpr double kZoomAtS = 2.0, kFlightS = 5.0;
  cigi::ViewDefinition zoom;
  zoom.leftEnabled = zoom.rightEnabled = zoom.topEnabled = zoom.bottomEnabled = true;
  zoom.leftDeg = -10.0f;
  zoom.rightDeg = 10.0f;
  zoom.topDeg = 7.5f;
  zoom.bottomDeg = -7.5f;
  const Steady::time_point start = Steady::now();
  pace(start, kFlightS, [&](std::uint32_t k, double tS) {
    if (tS >= kZoomAtS) host.sendDefinition(zoom);
    host.sendFrame(k, tS, tS);
  });
  const nlohmann::json s = finishService();
  ASSERT_FALSE(s.is_null());
  expectFieldsContinued(s);
  EXPECT_GE(s["host"]["view_definitions"].get<int>(), 60) << s.dump();
  EXPECT_EQ(s["host"]["view_definitions_ignored"].get<int>(), 0) << s.dump();

  // The picture: the zoom lands within a frame or two of the first Start of Frame after it.
  const std::vector<ReceivedSof> sofs = host.startOfFrames();
  const Steady::time_point zoomSent = start + seconds(kZoomAtS);
  const auto firstAfter =
      std::find_if(sofs.begin(), sofs.end(), [&](const ReceivedSof& r) { return r.arrival > zoomSent; });
  ASSERT_NE(firstAfter, sofs.end());
  const std::size_t zoomedAt = firstAfter->sof.igFrameNumber;
  expectPictureChangedAt(framesOfVideo(), zoomedAt, "zoom");
}

// The link's thread is named and scheduled like the field thread, one priority step below it:
// where the field thread got SCHED_FIFO, so did the link's.
TEST_F(HostFault, TheLinksThreadRunsAtRealtimePriorityLikeTheFieldThread) {
  startService(3.0);
  TestHost host(mPort, cigi::nativeByteOrder());
  ASSERT_TRUE(host.waitForIg(60.0)) << "no Start of Frame from the service";
  const std::optional<int> pid = servicePid(mDir / "fieldcast.toml");
  ASSERT_TRUE(pid.has_value());
  std::optional<int> field, link;
  for (const auto& [name, policy] : threadPolicies(*pid)) {
    if (name == "fc-field") field = policy;
    if (name == "fc-host-link") link = policy;
  }
  ASSERT_TRUE(field.has_value());
  ASSERT_TRUE(link.has_value()) << "no thread named fc-host-link";
  EXPECT_EQ(*link, *field) << "SCHED_FIFO is 1";
  std::printf("field thread policy %d, link thread policy %d\n", *field, *link);
  const nlohmann::json s = finishService();
  ASSERT_FALSE(s.is_null());
}
