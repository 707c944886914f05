// A real exchange between the service and `fieldcast-host --pcap --los`, judged by a third party
// and by the host's own terrain march:
// - tshark's CIGI dissector reads the host's capture: every frame CIGI 3, nothing malformed or
//   unknown, both directions with the packets each sends, the Entity Control values equal to what
//   the host logged it sent (--sent-log), and the Start of Frames' numbers consistent with the
//   capture's clock and with the host frames captured before them;
// - the IG's line-of-sight ranges agree with the host's fine march of the same terrain within one
//   voxel, over segments that meet the ground and segments that do not.
#include "../common/FreePort.h"
#include "../common/MachineStallWatch.h"
#include "../common/RunFieldcast.h"
#include "HostServiceConfig.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using fieldcast::testing::RunResult;

constexpr double kVoxelM = 2.0;  // the built-in terrain's spacing (builtin_size 512: a 1 km square)

using fieldcast::testing::freePort;

bool haveTshark() { return std::system("command -v tshark >/dev/null 2>&1") == 0; }

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(line);
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!line.empty() && line.back() == separator) parts.emplace_back();
  return parts;
}

// tshark prints doubles with 15 significant digits and floats with 6: equal within that rounding.
bool sameDouble(double printed, double sent) {
  return std::abs(printed - sent) <= 1e-14 * std::max(1.0, std::abs(sent));
}
bool sameFloat(double printed, double sent) {
  return std::abs(printed - sent) <= 6e-6 * std::max(std::abs(sent), 1e-30) + 1e-37;
}

class HostCapture : public ::testing::Test {
 protected:
  void SetUp() override {
    mDir = fs::temp_directory_path() / ("fieldcast_host_capture_" + std::to_string(getpid()));
    fs::remove_all(mDir);
    fs::create_directories(mDir / "cache");
    // Across the 1 km square at about 100 m/s, 260-300 m up: the LOS segments 400 m ahead swing
    // 60 m above and below the ground there, so some meet the terrain and some do not.
    std::ofstream(mDir / "flight.toml") << R"(name = "host capture pass"
end = "hold"
[[waypoint]]
t = 0
position = [100.0, 100.0, 300.0]
[[waypoint]]
t = 4
position = [500.0, 600.0, 260.0]
[[waypoint]]
t = 8
position = [900.0, 500.0, 280.0]
)";
    mIgPort = freePort();
    do mHostPort = freePort();
    while (mHostPort == mIgPort);
    std::ofstream(mDir / "fieldcast.toml") << fieldcast::testing::hostServiceConfig(mDir, mIgPort);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(mDir);
  }

  // The service for 10 s; the host waits for it, then flies 5 s with LOS requests, recording.
  void flyRecorded() {
    fieldcast::testing::MachineStallWatch stalls;
    const std::string config = (mDir / "fieldcast.toml").string();
    auto service = std::async(std::launch::async, [&] {
      return fieldcast::testing::runFieldcast("--config " + config + " --duration 10", 120);
    });
    const RunResult host = fieldcast::testing::runProgram(
        FIELDCAST_HOST_EXE,
        "--config " + config + " --flight " + (mDir / "flight.toml").string() + " --port " + std::to_string(mHostPort) +
            " --duration 5 --wait-for-ig 60 --los --time-of-day 2024-06-21T19:30" + " --pcap " + pcap() +
            " --sent-log " + (mDir / "sent.tsv").string() + " --summary " + (mDir / "host.json").string(),
        120);
    const RunResult run = service.get();
    mMachineFields = stalls.fieldsDueInStalls();
    ASSERT_EQ(host.exitCode, 0) << host.output;
    ASSERT_EQ(run.exitCode, 0) << run.output;
    mHost = nlohmann::json::parse(std::ifstream(mDir / "host.json"));
  }

  std::string pcap() const { return (mDir / "host.pcap").string(); }

  // tshark's output for the capture with the CIGI dissector on the IG's port.
  std::string tshark(const std::string& args, const std::string& outputName) const {
    const fs::path out = mDir / outputName;
    const std::string command = "tshark -n -r " + pcap() + " -d udp.port==" + std::to_string(mIgPort) + ",cigi " +
                                args + " >" + out.string() + " 2>" + (mDir / "tshark.err").string();
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    std::ostringstream text;
    text << std::ifstream(out).rdbuf();
    return text.str();
  }

  fs::path mDir;
  int mMachineFields = 0;  // fields due while the machine itself stood still during the flight
  std::uint16_t mIgPort = 0;
  std::uint16_t mHostPort = 0;
  nlohmann::json mHost;
};

TEST_F(HostCapture, TsharkReadsTheHostsCaptureAsWhatWasSent) {
  if (!haveTshark()) GTEST_SKIP() << "tshark not installed (scripts/install-deps.sh --interop installs it)";
  ASSERT_NO_FATAL_FAILURE(flyRecorded());
  const int captured = mHost["pcap_frames"].get<int>();
  ASSERT_GT(captured, 500) << mHost.dump();

  // Every frame dissected as CIGI 3, nothing flagged.
  const std::string dissection = tshark("-V", "dissection.txt");
  const auto count = [&](const std::regex& re) {
    return std::distance(std::sregex_iterator(dissection.begin(), dissection.end(), re), std::sregex_iterator());
  };
  EXPECT_EQ(count(std::regex(R"(^Frame \d+:)", std::regex::multiline)), captured);
  EXPECT_EQ(count(std::regex(R"(^Common Image Generator Interface \(3\))", std::regex::multiline)), captured);
  const std::regex flagged("malformed|unknown|expert info|exception", std::regex::icase);
  std::istringstream lines(dissection);
  int flaggedLines = 0;
  for (std::string line; std::getline(lines, line);) {
    if (std::regex_search(line, flagged) && ++flaggedLines <= 5) ADD_FAILURE() << "tshark -V: " << line;
  }
  EXPECT_EQ(flaggedLines, 0) << "full dissection: " << (mDir / "dissection.txt");

  // The fields, one line per frame.
  enum Column { Src, Dst, Ids, HostFrame, Lat, Lon, Alt, Yaw, Pitch, Roll, IgFrame, LastHostFrame, IgTicks, Time };
  const std::string table = tshark(
      "-T fields -E separator=/t -E occurrence=a -e udp.srcport -e udp.dstport -e cigi.packet_id"
      " -e cigi.ig_control.host_frame_number -e cigi.entity_control.lat_xoff -e cigi.entity_control.lon_yoff"
      " -e cigi.entity_control.alt_zoff -e cigi.entity_control.yaw -e cigi.entity_control.pitch"
      " -e cigi.entity_control.roll -e cigi.sof.ig_frame_number -e cigi.sof.last_host_frame_number"
      " -e cigi.sof.timestamp -e frame.time_epoch",
      "fields.tsv");

  // What the host says it sent, by host frame number.
  std::map<long, std::vector<double>> sent;
  std::ifstream sentLog(mDir / "sent.tsv");
  std::string line;
  std::getline(sentLog, line);  // header
  while (std::getline(sentLog, line)) {
    const std::vector<std::string> f = split(line, '\t');
    ASSERT_EQ(f.size(), 7u) << line;
    sent[std::stol(f[0])] = {std::stod(f[1]), std::stod(f[2]), std::stod(f[3]),
                             std::stod(f[4]), std::stod(f[5]), std::stod(f[6])};
  }
  ASSERT_EQ(static_cast<long>(sent.size()), mHost["host_frames_sent"].get<long>());

  std::set<int> hostIds, igIds;
  int frames = 0, compared = 0, badValues = 0, notCausal = 0;
  long newestHostFrame = -1;  // of the host messages captured so far (cause before effect)
  struct Sof {
    long igFrame;
    std::uint32_t ticks;
    double timeS;
  };
  std::vector<Sof> sofs;
  std::istringstream rows(table);
  while (std::getline(rows, line)) {
    ++frames;
    const std::vector<std::string> f = split(line, '\t');
    ASSERT_EQ(f.size(), 14u) << "frame " << frames << ": " << line;
    std::vector<int> ids;
    for (const std::string& id : split(f[Ids], ',')) ids.push_back(std::stoi(id));
    ASSERT_FALSE(ids.empty()) << "frame " << frames;
    if (std::stoi(f[Src]) == mHostPort && std::stoi(f[Dst]) == mIgPort) {
      EXPECT_EQ(ids.front(), 1) << "frame " << frames << ": a host message starts with IG Control";
      hostIds.insert(ids.begin(), ids.end());
      const long hostFrame = std::stol(f[HostFrame]);
      newestHostFrame = std::max(newestHostFrame, hostFrame);
      if (f[Lat].empty()) continue;  // IG Control alone, while waiting for the IG
      const auto it = sent.find(hostFrame);
      ASSERT_NE(it, sent.end()) << "frame " << frames << ": host frame " << hostFrame << " not in the sent log";
      const std::vector<double>& want = it->second;
      const bool same = sameDouble(std::stod(f[Lat]), want[0]) && sameDouble(std::stod(f[Lon]), want[1]) &&
                        sameDouble(std::stod(f[Alt]), want[2]) && sameFloat(std::stod(f[Yaw]), want[3]) &&
                        sameFloat(std::stod(f[Pitch]), want[4]) && sameFloat(std::stod(f[Roll]), want[5]);
      if (!same && ++badValues <= 5) ADD_FAILURE() << "frame " << frames << ": tshark " << line;
      ++compared;
    } else if (std::stoi(f[Src]) == mIgPort && std::stoi(f[Dst]) == mHostPort) {
      EXPECT_EQ(ids.front(), 101) << "frame " << frames << ": an IG message starts with Start of Frame";
      igIds.insert(ids.begin(), ids.end());
      // The last host frame the IG names was captured before its Start of Frame.
      if (std::stol(f[LastHostFrame]) > newestHostFrame) ++notCausal;
      sofs.push_back({std::stol(f[IgFrame]), static_cast<std::uint32_t>(std::stoul(f[IgTicks])), std::stod(f[Time])});
    } else {
      ADD_FAILURE() << "frame " << frames << " is neither host→IG nor IG→host: " << line;
    }
  }
  EXPECT_EQ(frames, captured);
  EXPECT_EQ(compared, static_cast<int>(sent.size())) << "every Entity Control sent was captured once";
  EXPECT_EQ(badValues, 0);
  EXPECT_EQ(notCausal, 0);
  // Both directions, with the packets each sends: IG Control, Entity Control, Rate Control,
  // Celestial Sphere Control, HAT/HOT Request, LOS Segment Request; Start of Frame, HAT/HOT
  // Response, LOS Response and Extended.
  for (const int id : {1, 2, 8, 9, 24, 25}) EXPECT_TRUE(hostIds.count(id)) << "no host packet " << id;
  for (const int id : {101, 102, 104, 105}) EXPECT_TRUE(igIds.count(id)) << "no IG packet " << id;

  // Start of Frame: one IG frame per field (59.94 Hz) by the capture's clock, and by its own
  // timestamps (10 µs ticks); frame numbers never go back and almost always step by one (a
  // late link thread may coalesce two fields; a stall of the machine itself skips the fields due
  // in it).
  ASSERT_GT(static_cast<int>(sofs.size()) + mMachineFields, 250);
  int steps = 0, singleSteps = 0;
  for (std::size_t k = 1; k < sofs.size(); ++k) {
    const long step = sofs[k].igFrame - sofs[k - 1].igFrame;
    EXPECT_GE(step, 1) << "Start of Frame " << k;
    ++steps;
    if (step == 1) ++singleSteps;
  }
  EXPECT_GE(singleSteps + mMachineFields, steps * 95 / 100);
  const Sof& first = sofs.front();
  const Sof& last = sofs.back();
  const auto fieldsBetween = static_cast<double>(last.igFrame - first.igFrame);
  EXPECT_NEAR(fieldsBetween / (last.timeS - first.timeS), 59.94, 1.0);  // capture clock, arrival jitter
  const std::uint32_t ticks = last.ticks - first.ticks;                 // they wrap at 2^32
  EXPECT_NEAR(ticks * 10e-6 / fieldsBetween, 1.0 / 59.94, 1e-5);        // display times
}

TEST_F(HostCapture, TsharkReadsTheTimeOfDayAsSent) {
  if (!haveTshark()) GTEST_SKIP() << "tshark not installed (scripts/install-deps.sh --interop installs it)";
  ASSERT_NO_FATAL_FAILURE(flyRecorded());
  // --time-of-day 2024-06-21T19:30: once a second, date and time valid, the ephemeris model on.
  const std::string table = tshark(
      "-Y cigi.celestial_sphere_control.hour -T fields -E separator=/t -e cigi.celestial_sphere_control.hour"
      " -e cigi.celestial_sphere_control.minute -e cigi.celestial_sphere_control.date"
      " -e cigi.celestial_sphere_control.date_time_valid -e cigi.celestial_sphere_control.ephemeris_enable",
      "celestial.tsv");
  std::istringstream rows(table);
  int packets = 0;
  for (std::string line; std::getline(rows, line); ++packets) EXPECT_EQ(line, "19\t30\t6212024\t1\t1");
  EXPECT_GE(packets, 5);  // 5 s of flight
}

TEST_F(HostCapture, LineOfSightRangesMatchTheHostsOwnMarch) {
  ASSERT_NO_FATAL_FAILURE(flyRecorded());
  const nlohmann::json& h = mHost;
  const int requests = h["los_requests"].get<int>();
  const int answers = h["los_answers"].get<int>();
  const int hits = h["los_hits"].get<int>();
  EXPECT_GT(requests, 250) << h.dump();
  EXPECT_GE(answers, requests * 95 / 100) << h.dump();
  // Both kinds of segment, by the IG and by the host's march alike.
  EXPECT_GE(hits, answers / 10) << h.dump();
  EXPECT_GE(answers - hits, answers / 10) << h.dump();
  EXPECT_EQ(h["los_disagreements"].get<int>(), 0) << h.dump();
  EXPECT_LE(h["los_range_error_max_m"].get<double>(), kVoxelM) << h.dump();
}

}  // namespace
