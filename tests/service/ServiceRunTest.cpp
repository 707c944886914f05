// The real service, run as a user runs it, on a small built-in terrain: fields at the right
// rate into a Y4M file, a clean stop on SIGTERM, and one clear line for each bad configuration.
#include "../common/MachineStallWatch.h"
#include "../common/RunFieldcast.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

using fieldcast::testing::RunResult;
RunResult run(const std::string& args, int timeoutS = 120) { return fieldcast::testing::runFieldcast(args, timeoutS); }

// A workspace with a small terrain cache shared by the tests of this run, a flight over it and
// a configuration that writes into the workspace.
class ServiceRun : public ::testing::Test {
 protected:
  static fs::path root() {
    static const fs::path dir = fs::temp_directory_path() / ("fieldcast_service_" + std::to_string(getpid()));
    return dir;
  }
  void SetUp() override {
    fs::create_directories(root() / "cache");
    mDir = root() / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(mDir);
    fs::create_directories(mDir);
    // 512 × 512 voxels at 2 m: a 1 km square, built in about a second.
    std::ofstream(mDir / "flight.toml") << R"(name = "test pass"
[[waypoint]]
t = 0
position = [100.0, 100.0, 350.0]
[[waypoint]]
t = 4
position = [500.0, 600.0, 300.0]
[[waypoint]]
t = 8
position = [900.0, 500.0, 320.0]
)";
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(mDir);
  }

  // Each call writes its own file, so several configurations can be prepared at once.
  std::string config(const std::string& extra = "") {
    const fs::path path = mDir / ("fieldcast" + std::to_string(mConfigs++) + ".toml");
    std::ofstream(path) << "[terrain]\nsource = \"builtin\"\ncache_dir = \"" << (root() / "cache").string()
                        << "\"\nbuiltin_size = 512\nmemory_budget_mb = 64\n"
                        << "[render]\nthreads = 2\nfov_deg = 60\n"
                        << "[output]\nrate = 59.94\nscan = \"interlaced\"\nwidth = 320\nheight = 240\n"
                        << "[motion]\nsource = \"flight\"\nflight = \"flight.toml\"\n"
                        << "[sinks.y4m]\nenabled = true\npath = \"out/video.y4m\"\n"
                        << "[metrics]\nsummary_json = \"out/summary.json\"\n"
                        << "[threads]\nrealtime_field_thread = false\n"
                        << extra;
    return path.string();
  }

  nlohmann::json summary() const { return nlohmann::json::parse(std::ifstream(mDir / "out/summary.json")); }

  // Frames in a Y4M file: every FRAME header, walking the file by the frame size.
  int y4mFrames(std::size_t frameBytes) const {
    std::ifstream in(mDir / "out/video.y4m", std::ios::binary);
    std::string header;
    std::getline(in, header);
    int frames = 0;
    std::string marker;
    while (std::getline(in, marker)) {
      if (marker.rfind("FRAME", 0) != 0) return -1;
      in.ignore(static_cast<std::streamsize>(frameBytes));
      if (!in) return -1;  // a truncated last frame
      ++frames;
    }
    return frames;
  }

  // Mean luma of rows [rowFrom, rowTo) of the last frame of the Y4M file (4:2:0, 320×240).
  double lastFrameLuma(int rowFrom, int rowTo) const {
    constexpr int kW = 320, kH = 240;
    constexpr std::size_t kFrameBytes = kW * kH * 3 / 2;
    std::ifstream in(mDir / "out/video.y4m", std::ios::binary);
    std::string line;
    std::getline(in, line);
    std::string luma(kW * kH, '\0');
    for (std::string marker; std::getline(in, marker);) {
      if (!in.read(luma.data(), kW * kH)) break;
      in.ignore(static_cast<std::streamsize>(kFrameBytes - kW * kH));
    }
    double sum = 0.0;
    for (int r = rowFrom; r < rowTo; ++r) {
      for (int c = 0; c < kW; ++c) sum += static_cast<unsigned char>(luma[static_cast<std::size_t>(r) * kW + c]);
    }
    return sum / ((rowTo - rowFrom) * kW);
  }

  // Luma (Y plane) of every `every`-th frame of the Y4M file (4:2:0, 320×240).
  std::vector<std::string> lumaFrames(int every) const {
    constexpr std::size_t kLuma = 320 * 240, kFrameBytes = kLuma * 3 / 2;
    std::ifstream in(mDir / "out/video.y4m", std::ios::binary);
    std::string line;
    std::getline(in, line);
    std::vector<std::string> frames;
    std::string luma(kLuma, '\0');
    for (int n = 0; std::getline(in, line); ++n) {
      if (!in.read(luma.data(), kLuma)) break;
      in.ignore(static_cast<std::streamsize>(kFrameBytes - kLuma));
      if (n % every == 0) frames.push_back(luma);
    }
    return frames;
  }

  fs::path mDir;
  int mConfigs = 0;
};

// Mean and standard deviation of one luma plane.
std::pair<double, double> lumaStats(const std::string& luma) {
  double sum = 0.0, sum2 = 0.0;
  for (const char c : luma) {
    const double v = static_cast<unsigned char>(c);
    sum += v;
    sum2 += v * v;
  }
  const double n = static_cast<double>(luma.size()), mean = sum / n;
  return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean))};
}

// Mean absolute difference of two luma planes.
double lumaChange(const std::string& a, const std::string& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sum += std::abs(static_cast<unsigned char>(a[i]) - static_cast<unsigned char>(b[i]));
  }
  return sum / static_cast<double>(a.size());
}

// Fields a run of `seconds` may miss on this machine: the tests share two cores with builds and
// other tests, and the field thread runs without real-time priority here (realtime_field_thread =
// false), so a busy moment can cost a field or two. An idle machine misses none (README); 2% of
// the fields plus 2 is what a loaded one was seen to stay within.
// Fields due while the machine itself stood still (MachineStallWatch.h) are allowed on top.
double missedAllowance(double seconds) { return 0.02 * seconds * 60000.0 / 1001.0 + 2.0; }

TEST_F(ServiceRun, EmitsEveryFieldForTheDuration) {
  fieldcast::testing::MachineStallWatch stalls;
  const RunResult r = run("--config " + config() + " --duration 3");
  const int machine = stalls.fieldsDueInStalls();
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json s = summary();
  // Every field of the schedule is accounted for: emitted, or missed when this shared machine
  // kept the field thread from its deadline (counted, never made up by a burst).
  const double expected = 3.0 * 60000.0 / 1001.0;
  const auto emitted = s.at("fields_emitted").get<double>();
  const auto missed = s.at("fields_missed").get<double>();
  EXPECT_NEAR(emitted + missed, expected, 1.0) << s.dump(2);
  EXPECT_LE(missed, missedAllowance(3.0) + machine)
      << "the field thread is behind its schedule (" << machine << " fields due while the machine stalled)\n"
      << s.dump(2);
  EXPECT_EQ(s.at("fields_black").get<int>(), 0) << s.dump(2);
  EXPECT_GT(s.at("frames_rendered").get<int>(), 0);
  // No field dropped by a sink — unless the machine took a CPU from the sink's worker while the
  // field thread ran on: at most the fields due in that stall
  EXPECT_LE(s.at("sinks_dropped").get<int>(), machine) << s.dump(2);
  // The fields show terrain: every sampled frame has structure (not black, not one flat colour),
  // and the picture moves with the flight.
  const std::vector<std::string> sampled = lumaFrames(10);
  ASSERT_GE(sampled.size(), 8u);
  for (std::size_t i = 0; i < sampled.size(); ++i) {
    const auto [mean, deviation] = lumaStats(sampled[i]);
    EXPECT_GT(mean, 30.0) << "frame " << i * 10 << " is (nearly) black";
    EXPECT_LT(mean, 235.0) << "frame " << i * 10 << " is white";
    EXPECT_GT(deviation, 12.0) << "frame " << i * 10 << " is flat (mean " << mean << ")";
    if (i > 0) {
      EXPECT_GT(lumaChange(sampled[i - 1], sampled[i]), 1.0)
          << "frames " << (i - 1) * 10 << " and " << i * 10 << " are alike";
    }
  }
  // Every output frame is in the file, a missed field repeated in its place so the video keeps
  // time: two fields per interlaced frame (a last lone field is completed at close), 4:2:0 320×240.
  const int frames = y4mFrames(320 * 240 * 3 / 2);
  EXPECT_EQ(frames, (static_cast<int>(emitted + missed) + 1) / 2) << r.output;
}

TEST_F(ServiceRun, WarmsUpBeforeTheFirstFieldAndReportsTheStartUp) {
  fieldcast::testing::MachineStallWatch stalls;
  const RunResult r = run("--config " + config() + " --duration 2");
  const int machine = stalls.fieldsDueInStalls();
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json s = summary();
  const nlohmann::json& startup = s.at("startup");
  // The field thread warped a real frame before the field clock existed.
  EXPECT_GE(startup.at("warm_up_frame").get<int>(), 1) << s.dump(2);
  EXPECT_GT(startup.at("warm_up_warp_ms").get<double>(), 0.0) << s.dump(2);
  EXPECT_LE(s.at("fields_missed_first_second").get<double>(), missedAllowance(1.0) + machine) << s.dump(2);
  // Fallbacks by reason add up to the total.
  const nlohmann::json& reasons = s.at("warp_fallbacks_by_reason");
  EXPECT_EQ(reasons.at("few_points").get<int>() + reasons.at("all_sky").get<int>() +
                reasons.at("degenerate").get<int>() + reasons.at("no_range_image").get<int>(),
            s.at("warp_fallbacks").get<int>());
  // The log reports the start-up (the per-interval tile misses are ServiceMetricsTest's).
  EXPECT_NE(r.output.find("start-up: "), std::string::npos) << r.output;
}

TEST_F(ServiceRun, TheMeshWarpGetsItsRangeImageAndShowsTheTerrain) {
  // warp.kind = "mesh" must turn the renderer's range image on: without it every field would
  // fall back to the quadratic (reason no_range_image).
  fieldcast::testing::MachineStallWatch stalls;
  const RunResult r = run("--config " + config("[warp]\nkind = \"mesh\"\n") + " --duration 2");
  const int machine = stalls.fieldsDueInStalls();
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json s = summary();
  EXPECT_GT(s.at("fields_emitted").get<int>(), 100 - machine) << s.dump(2);
  EXPECT_EQ(s.at("warp_fallbacks_by_reason").at("no_range_image").get<int>(), 0) << s.dump(2);
  EXPECT_EQ(s.at("fields_black").get<int>(), 0) << s.dump(2);
  const std::vector<std::string> sampled = lumaFrames(10);
  ASSERT_GE(sampled.size(), 5u);
  for (std::size_t i = 0; i < sampled.size(); ++i) {
    const auto [mean, deviation] = lumaStats(sampled[i]);
    EXPECT_GT(mean, 30.0) << "frame " << i * 10 << " is (nearly) black";
    EXPECT_GT(deviation, 12.0) << "frame " << i * 10 << " is flat (mean " << mean << ")";
  }
}

TEST_F(ServiceRun, VisibilityDefaultsFromTheDatabaseAndTheKeyIsHonoured) {
  // The 1 km test terrain: three quarters of its extent is below the 3 km floor.
  const RunResult byExtent = run("--config " + config() + " --duration 0.5");
  ASSERT_EQ(byExtent.exitCode, 0) << byExtent.output;
  EXPECT_EQ(summary().at("visibility_m").get<double>(), 3000.0) << summary().dump(2);
  EXPECT_NE(byExtent.output.find("visibility 3000 m (from the database's extent)"), std::string::npos);
  const RunResult given = run("--config " + config("") + " --set render.visibility_m=1800 --duration 0.5");
  ASSERT_EQ(given.exitCode, 0) << given.output;
  EXPECT_EQ(summary().at("visibility_m").get<double>(), 1800.0) << summary().dump(2);
}

TEST_F(ServiceRun, AFlightThatEndsWithStopEndsTheRun) {
  std::ofstream(mDir / "short.toml") << R"(name = "short"
end = "stop"
[[waypoint]]
t = 0
position = [100.0, 100.0, 350.0]
[[waypoint]]
t = 1.5
position = [300.0, 400.0, 340.0]
)";
  // No --duration: the flight's end ends the run, with every field up to it accounted for.
  const RunResult r = run("--config " + config("") + " --set motion.flight=" + (mDir / "short.toml").string(), 60);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json s = summary();
  const double fields = s.at("fields_emitted").get<double>() + s.at("fields_missed").get<double>();
  EXPECT_GT(fields, 1.5 * 60000.0 / 1001.0 - 5.0) << s.dump(2);
  EXPECT_LT(fields, 1.5 * 60000.0 / 1001.0 + 5.0) << s.dump(2);
}

TEST_F(ServiceRun, SigtermMidRunStopsCleanlyWithACompleteFile) {
  const std::string command =
      "exec " + std::string(FIELDCAST_EXE) + " --config " + config() + " > " + (mDir / "log.txt").string() + " 2>&1";
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    execl("/bin/sh", "sh", "-c", command.c_str(), nullptr);
    _exit(127);
  }
  // Let it render and emit for a while, then stop it as systemd would.
  const auto giveUp = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(mDir / "out/video.y4m") || fs::file_size(mDir / "out/video.y4m") < 2'000'000) {
    ASSERT_LT(std::chrono::steady_clock::now(), giveUp) << "no video after 60 s";
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  kill(child, SIGTERM);
  int status = 0;
  for (int i = 0; i < 300 && waitpid(child, &status, WNOHANG) == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (waitpid(child, &status, WNOHANG) == 0) {
    kill(child, SIGKILL);
    waitpid(child, &status, 0);
    FAIL() << "did not stop within 30 s of SIGTERM";
  }
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const int frames = y4mFrames(320 * 240 * 3 / 2);
  EXPECT_GT(frames, 10);  // whole frames only: nothing truncated
  const nlohmann::json s = summary();
  EXPECT_EQ((s.at("fields_emitted").get<int>() + s.at("fields_missed").get<int>() + 1) / 2, frames);
}

TEST_F(ServiceRun, FrameTimeControllerCoarsensAndTheSummarySaysHowFar) {
  // Without a target every frame is rendered at the configured knob.
  const RunResult fixed = run("--config " + config() + " --duration 2");
  ASSERT_EQ(fixed.exitCode, 0) << fixed.output;
  EXPECT_EQ(summary().at("mean_quality").get<double>(), 1.0) << summary().dump(2);
  EXPECT_EQ(summary().at("frames_grazing").get<int>(), 0);
  // A target no frame can meet: the controller turns the grazing rule on and coarsens. It counts
  // only frames rendered with its current knobs, and the first frames are rendered at 0.25, below
  // its floor of 0.5: the render loop must hand its knob to the renderer even when it skips a frame.
  const RunResult held =
      run("--config " + config() + " --set render.quality=0.25 --set render.target_frame_ms=0.1 --duration 2");
  ASSERT_EQ(held.exitCode, 0) << held.output;
  const nlohmann::json s = summary();
  EXPECT_GT(s.at("mean_quality").get<double>(), 2.0) << s.dump(2);
  EXPECT_GT(s.at("frames_grazing").get<int>(), 0) << s.dump(2);
  EXPECT_NE(held.output.find("grazing-angle rule on for"), std::string::npos) << held.output;
}

TEST_F(ServiceRun, TheChannelLooksWhereItsViewOffsetPoints) {
  // Straight ahead the lower half of the picture is terrain; the same flight with the channel's
  // eye pitched 90° up sees sky there, which is much brighter. An offset that did not reach the
  // renderer and the warp would leave the two pictures alike (within a few levels). The haze is
  // held at 12 km: the test terrain's default (3 km) lightens the terrain towards the sky's colour.
  const RunResult ahead = run("--config " + config() + " --set render.visibility_m=12000 --duration 2");
  ASSERT_EQ(ahead.exitCode, 0) << ahead.output;
  const double aheadLuma = lastFrameLuma(120, 240);
  const RunResult up =
      run("--config " + config("[view]\noffset_deg = [0, 90, 0]\n") + " --set render.visibility_m=12000 --duration 2");
  ASSERT_EQ(up.exitCode, 0) << up.output;
  const double upLuma = lastFrameLuma(120, 240);
  EXPECT_GT(upLuma, aheadLuma + 25.0) << "ahead " << aheadLuma << ", up " << upLuma;
  EXPECT_EQ(summary().at("fields_black").get<int>(), 0);
}

TEST_F(ServiceRun, AFlightsScriptedEntityIsDrawnInItsFields) {
  // The test pass with a light aircraft (config/models/aircraft.vox at three times its size, 35 m
  // in span) hanging 60 m ahead of where the ownship is at 1 s: the fields around 1 s show it in
  // their middle; at 1.4 s the ownship flies through it (the entity's box then covers the frame).
  std::ofstream(mDir / "traffic.toml") << std::ifstream(mDir / "flight.toml").rdbuf() << R"(
[[entity]]
name = "parked in the air"
model = ")" << FIELDCAST_SOURCE_DIR << R"(/config/models/aircraft.vox"
scale = 3
[[entity.waypoint]]
t = 0
position = [232.5, 310.6, 326.0]
[[entity.waypoint]]
t = 10
position = [232.5, 310.6, 326.0]
)";
  const auto middleFields = [&](const std::string& flight) {
    const RunResult r =
        run("--config " + config() + " --set motion.flight=" + (mDir / flight).string() + " --duration 2");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(summary().at("fields_black").get<int>(), 0);
    return lumaFrames(1);
  };
  const std::vector<std::string> bare = middleFields("flight.toml");
  const std::vector<std::string> traffic = middleFields("traffic.toml");
  ASSERT_GT(bare.size(), 33u);
  ASSERT_GT(traffic.size(), 33u);
  // Frames 28–32 (0.93–1.07 s): pixels of the middle third that changed by more than 40 levels
  const auto changed = [](const std::string& a, const std::string& b) {
    int n = 0;
    for (int r = 80; r < 160; ++r)
      for (int c = 107; c < 213; ++c) {
        const std::size_t k = static_cast<std::size_t>(r) * 320 + static_cast<std::size_t>(c);
        n += std::abs(static_cast<unsigned char>(a[k]) - static_cast<unsigned char>(b[k])) > 40;
      }
    return n;
  };
  for (std::size_t f = 28; f <= 32; ++f) {
    const int withAircraft = changed(bare[f], traffic[f]), alone = changed(bare[f], bare[f + 1]);
    std::printf("frame %zu: %d px of the middle changed by the aircraft, %d from one bare frame to the next\n", f,
                withAircraft, alone);
    EXPECT_GT(withAircraft, 600);  // seen almost edge on in a bank: the wing and the fuselage
    EXPECT_GT(withAircraft, 3 * alone);
  }
}

TEST_F(ServiceRun, BadConfigurationsFailWithOneClearLine) {
  struct Case {
    const char* what;
    std::string args;
    const char* expected;
  };
  const Case cases[] = {
      {"unknown key", "--config " + config("[warp]\nspeed = 3\n"), "speed"},
      {"wrong type", "--config " + config() + " --set output.width=\\\"wide\\\"", "output.width"},
      {"missing database", "--config " + config() + " --set terrain.source=\\\"/nonexistent/terrain.fcdb\\\"",
       "/nonexistent/terrain.fcdb"},
      {"unwritable output", "--config " + config() + " --y4m /proc/fieldcast/video.y4m", "/proc/fieldcast"},
      {"bad sync line", "--config " + config() + " --set input.sync=\\\"gpiochip7:3\\\"", "gpiochip7"},
      {"bad device path",
       "--config " + config() + " --set motion.source=\\\"stick\\\" --set input.stick=\\\"/dev/input/event99\\\"",
       "/dev/input/event99"},
  };
  for (const Case& c : cases) {
    const RunResult r = run(c.args + " --duration 2", 60);
    EXPECT_NE(r.exitCode, 0) << c.what << ":\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.what << ":\n" << r.output;
    // One line says what is wrong; log lines before it are information, not errors.
    std::size_t errors = 0;
    for (std::size_t at = 0; at < r.output.size(); at = r.output.find('\n', at) + 1) {
      if (r.output.compare(at, 11, "fieldcast: ") == 0) ++errors;
      if (r.output.find('\n', at) == std::string::npos) break;
    }
    EXPECT_EQ(errors, 1u) << c.what << ":\n" << r.output;
  }
}

}  // namespace
