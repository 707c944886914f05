// The host's commands acted on mid-run, each against the real `fieldcast` service driven by the
// test's own host (HostTestRig.h): a database switch (IG Control's database number), a turn of
// the eye (View Control), a zoom (View Definition) — each must cost no field, and the picture
// must change where the command took effect — and the link thread's scheduling.
#include "HostTestRig.h"

namespace {

using namespace fieldcast::host_test;

class HostCommand : public HostServiceTest {};

// ---- A database switch mid-run ------------------------------------------------------------------

// IG Control asks for database 2 (the built-in terrain of another seed) while the ownship holds
// still over the middle of the terrain: Start of Frame says 1, then −2 while it loads (a fresh
// built-in terrain is generated: longer than a field), then 2; the video goes on without a
// missed or black field, and the picture, steady before, is another terrain after.
class HostDatabaseSwitch : public HostServiceTest {
 protected:
  void SetUp() override {
    HostServiceTest::SetUp();
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
TEST_F(HostCommand, ViewControlTurnsTheEyeWithoutLosingAField) {
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
TEST_F(HostCommand, ViewDefinitionZoomsWithoutLosingAField) {
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
TEST_F(HostCommand, TheLinksThreadRunsAtRealtimePriorityLikeTheFieldThread) {
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

}  // namespace
