// The software frame lock ([lock]) between fieldcast processes on loopback, as a rig runs them:
// every channel numbers its fields alike and shows field k at the same instant and pose; a
// channel killed and restarted rejoins at the others' field without disturbing them; a channel
// that hears an earlier lock while running moves onto it.
#include "../common/FreePort.h"
#include "../common/MachineStallWatch.h"

#include <io_bridge/FieldLockLink.h>

#include "../../tools/rig/ChannelRun.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using fieldcast::testing::freePort;
using fieldcast::tools::byNumber;
using fieldcast::tools::LoggedField;
using fieldcast::tools::readFieldLog;

// One fieldcast process, its output in `log`. Killed if it outlives the test's bound.
class Channel {
 public:
  Channel(const std::string& args, const fs::path& log) {
    const std::string command = "exec " + std::string(FIELDCAST_EXE) + " " + args + " > " + log.string() + " 2>&1";
    mPid = fork();
    if (mPid == 0) {
      execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  ~Channel() {
    if (mPid > 0 && !mDone) {
      kill(mPid, SIGKILL);
      waitpid(mPid, nullptr, 0);
    }
  }
  /// The exit code once it has exited (−1: killed, or still running after `timeout`, then killed).
  int wait(std::chrono::seconds timeout = 90s) {
    const auto giveUp = std::chrono::steady_clock::now() + timeout;
    int status = 0;
    while (waitpid(mPid, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > giveUp) {
        kill(mPid, SIGKILL);
        waitpid(mPid, &status, 0);
        break;
      }
      std::this_thread::sleep_for(20ms);
    }
    mDone = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  void killNow() {
    kill(mPid, SIGKILL);
    wait();
  }

 private:
  pid_t mPid = -1;
  bool mDone = false;
};

// Waits up to a minute for `text` to appear in the file at `path` (a channel's log).
bool waitForLog(const fs::path& path, const std::string& text) {
  for (int i = 0; i < 1200; ++i) {
    std::ifstream in(path);
    const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (content.find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(50ms);
  }
  return false;
}

class FrameLock : public ::testing::Test {
 protected:
  static fs::path root() {
    static const fs::path dir = fs::temp_directory_path() / ("fieldcast_lock_" + std::to_string(getpid()));
    return dir;
  }
  void SetUp() override {
    fs::create_directories(root() / "cache");
    mDir = root() / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(mDir);
    fs::create_directories(mDir);
    std::ofstream(mDir / "flight.toml") << R"(name = "lock pass"
[[waypoint]]
t = 0
position = [100.0, 100.0, 350.0]
[[waypoint]]
t = 30
position = [900.0, 800.0, 300.0]
)";
    for (auto& port : mPorts) port = freePort();
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(mDir);
  }

  // Channel `i` of three (yawed −60°, 0°, +60°), locked to the other two; its field log and
  // summary are `name`.csv and `name`.json.
  std::string channelArgs(int i, const std::string& name, double durationS, const std::string& lockExtra = "") {
    const fs::path config = mDir / (name + ".toml");
    std::ofstream out(config);
    out << "[terrain]\nsource = \"builtin\"\ncache_dir = \"" << (root() / "cache").string()
        << "\"\nbuiltin_size = 512\nmemory_budget_mb = 64\n"
        << "[render]\nthreads = 1\nfov_deg = 60\nmax_rate_hz = 15\n"
        << "[view]\noffset_deg = [" << (i - 1) * 60 << ", 0, 0]\n"
        << "[output]\nrate = 59.94\nscan = \"interlaced\"\nwidth = 160\nheight = 120\n"
        << "[motion]\nsource = \"flight\"\nflight = \"flight.toml\"\n"
        << "[lock]\nlisten = \"127.0.0.1:" << mPorts[i] << "\"\npeers = [";
    const char* separator = "";
    for (int j = 0; j < 3; ++j) {
      if (j == i) continue;
      out << separator << "\"127.0.0.1:" << mPorts[j] << "\"";
      separator = ", ";
    }
    out << "]\n"
        << lockExtra << "[metrics]\nsummary_json = \"" << name << ".json\"\nfield_log = \"" << name << ".csv\"\n"
        << "[threads]\nrealtime_field_thread = false\nrealtime_host_thread = false\n";
    out.close();
    return "--config " + config.string() + " --duration " + std::to_string(durationS);
  }

  nlohmann::json summary(const std::string& name) const {
    return nlohmann::json::parse(std::ifstream(mDir / (name + ".json")));
  }

  fs::path mDir;
  std::uint16_t mPorts[3] = {};
};

// Fields both channels made: the same display time and the same ownship position; their count.
int expectSameInstants(const std::map<std::uint64_t, LoggedField>& a, const std::map<std::uint64_t, LoggedField>& b,
                       const char* what) {
  int common = 0;
  for (const auto& [k, field] : b) {
    const auto other = a.find(k);
    if (other == a.end()) continue;
    ++common;
    EXPECT_EQ(field.displayNs, other->second.displayNs) << what << ": field " << k;
    EXPECT_NEAR(field.xM, other->second.xM, 1e-3) << what << ": field " << k;
    EXPECT_NEAR(field.yM, other->second.yM, 1e-3) << what << ": field " << k;
    if (::testing::Test::HasFailure()) break;
  }
  return common;
}

TEST_F(FrameLock, AChannelKilledAndRestartedRejoinsWithoutDisturbingTheOthers) {
  fieldcast::testing::MachineStallWatch stalls;
  // Each channel starts once the one before has begun its fields (its log says how it locked)
  Channel left(channelArgs(0, "left", 18), mDir / "left.log");
  ASSERT_TRUE(waitForLog(mDir / "left.log", "frame lock: this channel's field 0"));
  Channel centre(channelArgs(1, "centre", 13), mDir / "centre.log");
  ASSERT_TRUE(waitForLog(mDir / "centre.log", "frame lock: joined"));
  {
    Channel right(channelArgs(2, "right_first", 30), mDir / "right_first.log");
    ASSERT_TRUE(waitForLog(mDir / "right_first.log", "frame lock: joined"));
    std::this_thread::sleep_for(5s);
    right.killNow();  // SIGKILL: no summary, no goodbye
  }
  std::this_thread::sleep_for(1s);
  Channel rightAgain(channelArgs(2, "right", 4), mDir / "right.log");
  ASSERT_EQ(rightAgain.wait(), 0) << std::ifstream(mDir / "right.log").rdbuf();
  ASSERT_EQ(centre.wait(), 0) << std::ifstream(mDir / "centre.log").rdbuf();
  ASSERT_EQ(left.wait(), 0) << std::ifstream(mDir / "left.log").rdbuf();
  const int machine = stalls.fieldsDueInStalls();

  const nlohmann::json l = summary("left"), c = summary("centre"), r = summary("right");
  // One lock: the first channel's epoch; the others joined it at start, nobody moved later
  EXPECT_EQ(l["lock"]["first_field"], 0);
  const std::uint64_t centreFirst = c["lock"]["first_field"].get<std::uint64_t>();
  EXPECT_GT(centreFirst, 0u);
  EXPECT_EQ(c["lock"]["epoch_ns"], l["lock"]["epoch_ns"]);
  EXPECT_EQ(r["lock"]["epoch_ns"], l["lock"]["epoch_ns"]);
  for (const auto* s : {&l, &c, &r}) {
    EXPECT_EQ((*s)["lock"]["relocks"], 0);
    EXPECT_EQ((*s)["lock"]["malformed"], 0);
    EXPECT_EQ((*s)["lock"]["strangers"], 0);
  }
  // The restarted channel joined at the field the others were at (more than six seconds after
  // the centre one began), a frame's first field
  const std::uint64_t rejoined = r["lock"]["first_field"].get<std::uint64_t>();
  EXPECT_GT(rejoined, centreFirst + 6 * 59);
  EXPECT_EQ(rejoined % 2, 0u);
  // The others were not disturbed: no field black, none missed beyond what a machine shared with
  // the other tests may cost (as ServiceRun allows, with the fields due while the machine itself
  // stood still), the schedule unbroken
  for (const auto* s : {&l, &c, &r}) {
    EXPECT_LE((*s)["fields_missed"].get<double>(), 0.02 * 18 * 59.94 + 2 + machine) << s->dump();
    EXPECT_EQ((*s)["fields_black"], 0) << s->dump();
  }

  const auto left_ = byNumber(readFieldLog((mDir / "left.csv").string()));
  const auto centre_ = byNumber(readFieldLog((mDir / "centre.csv").string()));
  const auto right_ = byNumber(readFieldLog((mDir / "right.csv").string()));
  const auto leftMissed = l["fields_missed"].get<std::size_t>();
  ASSERT_EQ(left_.size(), l["fields_emitted"].get<std::size_t>());
  // The left channel's fields run from field 0 without a jump while the right one died and came
  // back: every field of the schedule emitted or missed
  EXPECT_EQ(left_.rbegin()->first + 1, left_.size() + leftMissed);
  EXPECT_LE(right_.begin()->first - rejoined, r["fields_missed"].get<std::uint64_t>());
  // Field k: one display time and one ownship position in every channel (the left one outlives
  // the others)
  EXPECT_GE(expectSameInstants(left_, centre_, "left/centre") + leftMissed, centre_.size());
  EXPECT_GE(expectSameInstants(left_, right_, "left/right") + leftMissed, right_.size());
  EXPECT_GE(right_.size() + r["fields_missed"].get<std::size_t>(), 4u * 59u);
  // The first run of the right channel numbered its fields alike too, until it was killed
  const auto firstRun = byNumber(readFieldLog((mDir / "right_first.csv").string()));
  EXPECT_GT(expectSameInstants(left_, firstRun, "left/killed right") + machine, 4 * 59);
}

TEST_F(FrameLock, TwoChannelsLockOnTheTaiClock) {
  // As channels on two machines disciplined by PTP would: the epoch crosses as an instant of
  // CLOCK_TAI, each channel converting to and from its own CLOCK_MONOTONIC.
  Channel left(channelArgs(0, "left", 7, "clock = \"tai\"\n"), mDir / "left.log");
  ASSERT_TRUE(waitForLog(mDir / "left.log", "frame lock: this channel's field 0"));
  Channel centre(channelArgs(1, "centre", 4, "clock = \"tai\"\n"), mDir / "centre.log");
  ASSERT_EQ(centre.wait(), 0) << std::ifstream(mDir / "centre.log").rdbuf();
  ASSERT_EQ(left.wait(), 0) << std::ifstream(mDir / "left.log").rdbuf();
  const nlohmann::json l = summary("left"), c = summary("centre");
  EXPECT_EQ(l["lock"]["first_field"], 0);
  EXPECT_GT(c["lock"]["first_field"].get<std::uint64_t>(), 0u);
  EXPECT_EQ(l["lock"]["relocks"], 0);
  EXPECT_EQ(c["lock"]["relocks"], 0);
  const auto epochGap = l["lock"]["epoch_ns"].get<std::int64_t>() - c["lock"]["epoch_ns"].get<std::int64_t>();
  EXPECT_LT(std::abs(epochGap), fieldcast::io::kSameLockTolerance.count());
  // Field k at one instant, to the conversion's precision
  const auto left_ = byNumber(readFieldLog((mDir / "left.csv").string()));
  const auto centre_ = byNumber(readFieldLog((mDir / "centre.csv").string()));
  int common = 0;
  for (const auto& [k, field] : centre_) {
    const auto other = left_.find(k);
    if (other == left_.end()) continue;
    ++common;
    ASSERT_LT(std::abs(field.displayNs - other->second.displayNs), fieldcast::io::kSameLockTolerance.count())
        << "field " << k;
  }
  EXPECT_GT(common + l["fields_missed"].get<int>(), 3 * 59);
}

TEST_F(FrameLock, AChannelThatHearsAnEarlierLockWhileRunningMovesOntoIt) {
  // One channel alone; the test plays a second channel whose lock began earlier, and announces
  // it only once the first is running.
  const int test = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in self{};
  self.sin_family = AF_INET;
  self.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  self.sin_port = htons(mPorts[1]);
  ASSERT_EQ(bind(test, reinterpret_cast<const sockaddr*>(&self), sizeof self), 0);
  fieldcast::testing::MachineStallWatch stalls;
  Channel alone(channelArgs(0, "alone", 6), mDir / "alone.log");  // announces to ports 1 and 2

  // Its announcement, once it runs: its epoch
  std::uint8_t buffer[64];
  timeval timeout{30, 0};
  setsockopt(test, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  const ssize_t bytes = recv(test, buffer, sizeof buffer, 0);
  ASSERT_EQ(bytes, 40) << "no announcement from the channel within 30 s";
  const auto heard = fieldcast::io::decodeLockAnnouncement(std::span(buffer, 40));
  ASSERT_TRUE(heard);
  std::this_thread::sleep_for(1s);
  // Ours: field 0 was 1000.25 fields before its
  fieldcast::io::LockAnnouncement earlier = *heard;
  const fieldcast::RationalRate rate{60000, 1001};
  earlier.epoch = heard->epoch - rate.tickOffset(1000) - rate.period() / 4;
  earlier.senderPid = static_cast<std::uint32_t>(getpid());
  const auto datagram = fieldcast::io::encodeLockAnnouncement(earlier);
  sockaddr_in to = self;
  to.sin_port = htons(mPorts[0]);
  for (int i = 0; i < 3; ++i) {
    sendto(test, datagram.data(), datagram.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
    std::this_thread::sleep_for(100ms);
  }
  ASSERT_EQ(alone.wait(), 0) << std::ifstream(mDir / "alone.log").rdbuf();
  const int machine = stalls.fieldsDueInStalls();
  close(test);

  const nlohmann::json s = summary("alone");
  EXPECT_EQ(s["lock"]["relocks"], 1);
  EXPECT_EQ(s["lock"]["epoch_ns"], earlier.epoch.time_since_epoch().count());
  // Before: its own numbering; after: ours, 1000 and some fields on; the display times go on
  // rising by one field (once by up to two: the interlaced order is kept), never back. (A field
  // missed on this shared machine is a gap of its own periods.)
  const auto fields = byNumber(readFieldLog((mDir / "alone.csv").string()));
  std::uint64_t previous = 0;
  std::int64_t previousNs = 0;
  int jumps = 0;
  for (const auto& [k, f] : fields) {
    if (previousNs != 0) {
      const std::int64_t step = f.displayNs - previousNs;
      if (k > previous + 1000) {
        ++jumps;
        EXPECT_EQ(k % 2, (previous + 1) % 2) << "the field order is kept";
        EXPECT_GT(step, 0);
        // (and a period more for each field due while the machine itself stood still)
        EXPECT_LT(step, (3 + machine) * rate.period().count());
        const std::int64_t onOurs = f.displayNs - earlier.epoch.time_since_epoch().count();
        EXPECT_EQ(onOurs, rate.tickOffset(static_cast<std::int64_t>(k)).count()) << "field " << k << " on our schedule";
      } else {
        const auto gap =
            rate.tickOffset(static_cast<std::int64_t>(k)) - rate.tickOffset(static_cast<std::int64_t>(previous));
        EXPECT_EQ(step, gap.count()) << "field " << k;
      }
    }
    previous = k;
    previousNs = f.displayNs;
  }
  EXPECT_EQ(jumps, 1);
}

}  // namespace
