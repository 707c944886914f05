// The per-field record: its CSV lines, the ring's drop count when the writer falls behind, and an
// unwritable path named at start.
#include "FieldLog.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fieldcast::app {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  return fs::temp_directory_path() / ("fieldcast_field_log_" + std::to_string(getpid())) / name;
}

std::vector<std::string> lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

FieldRecord record(std::uint64_t field) {
  FieldRecord r;
  r.fieldNumber = field;
  r.displayNs = 2'000'000'000 + static_cast<std::int64_t>(field) * 16'683'333;
  r.emittedNs = r.displayNs - 3'000'000;
  r.pose = Pose{{100.5, -20.25, 300.0}, radians(90.0), radians(-10.0), radians(30.0)};
  r.frameNumber = 40 + field;
  r.framePoseNs = r.displayNs - 12'000'000;
  return r;
}

TEST(FieldLog, WritesAHeaderAndALinePerField) {
  const fs::path path = scratch("lines.csv");
  {
    FieldLog log(path);
    FieldRecord host = record(1);
    host.hasHostSample = true;
    host.hostFrame = 812;
    host.hostArrivalNs = 1'999'000'000;
    host.marginPx = 37;
    FieldRecord black = record(2);
    black.black = true;
    EXPECT_TRUE(log.push(record(0)));
    EXPECT_TRUE(log.push(host));
    EXPECT_TRUE(log.push(black));
    log.stop();
    EXPECT_EQ(log.written(), 3u);
    EXPECT_EQ(log.dropped(), 0u);
  }
  const std::vector<std::string> got = lines(path);
  ASSERT_EQ(got.size(), 4u);
  EXPECT_EQ(got[0],
            "field,display_ns,emitted_ns,x_east_m,y_north_m,z_up_m,heading_deg,pitch_deg,roll_deg,frame,frame_pose_ns,"
            "black,margin_px,host_frame,host_arrival_ns");
  EXPECT_EQ(got[1],
            "0,2000000000,1997000000,100.5000,-20.2500,300.0000,90.000000,-10.000000,30.000000,40,1988000000,0,0,,");
  EXPECT_EQ(got[2],
            "1,2016683333,2013683333,100.5000,-20.2500,300.0000,90.000000,-10.000000,30.000000,41,2004683333,0,37,812,"
            "1999000000");
  EXPECT_EQ(got[3].substr(0, 2), "2,");
  EXPECT_NE(got[3].find(",42,2021366666,1,0,,"), std::string::npos) << got[3];
  fs::remove_all(path.parent_path());
}

// Without its writer running the ring fills: what does not fit is dropped and counted, what fits
// is written when the log stops.
TEST(FieldLog, AFullRingDropsAndCounts) {
  const fs::path path = scratch("full.csv");
  FieldLog log(path, 4, false);
  int accepted = 0;
  for (std::uint64_t k = 0; k < 7; ++k) accepted += log.push(record(k)) ? 1 : 0;
  EXPECT_EQ(accepted, 4);
  EXPECT_EQ(log.dropped(), 3u);
  log.stop();
  EXPECT_EQ(log.written(), 4u);
  const std::vector<std::string> got = lines(path);
  ASSERT_EQ(got.size(), 5u);
  EXPECT_EQ(got[4].substr(0, 2), "3,");  // the first four kept, in order
  fs::remove_all(path.parent_path());
}

// The writer thread drains while the producer pushes more than the ring holds.
TEST(FieldLog, TheWriterDrainsAsFieldsCome) {
  const fs::path path = scratch("drained.csv");
  FieldLog log(path, 8);
  std::uint64_t dropped = 0;
  for (std::uint64_t k = 0; k < 64; ++k) {
    while (!log.push(record(k))) {  // wait for the writer, as a field period would
      ++dropped;
      usleep(1000);
    }
  }
  log.stop();
  EXPECT_EQ(log.written(), 64u);
  EXPECT_EQ(log.dropped(), dropped);
  EXPECT_EQ(lines(path).size(), 65u);
  fs::remove_all(path.parent_path());
}

TEST(FieldLog, AnUnwritablePathIsNamedAtStart) {
  try {
    FieldLog log("/proc/fieldcast/fields.csv");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("metrics.field_log: cannot write /proc/fieldcast/fields.csv"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace fieldcast::app
