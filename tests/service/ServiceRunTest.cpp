// The real service, run as a user runs it, on a small built-in terrain: fields at the right
// rate into a Y4M file, a clean stop on SIGTERM, and one clear line for each bad configuration.
#include "../common/RunFieldcast.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

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

  fs::path mDir;
  int mConfigs = 0;
};

TEST_F(ServiceRun, EmitsEveryFieldForTheDuration) {
  const RunResult r = run("--config " + config() + " --duration 3");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json s = summary();
  // Every field of the schedule is accounted for: emitted, or missed when this shared machine
  // kept the field thread from its deadline (counted, never made up by a burst).
  const double expected = 3.0 * 60000.0 / 1001.0;
  const auto emitted = s.at("fields_emitted").get<double>();
  const auto missed = s.at("fields_missed").get<double>();
  EXPECT_NEAR(emitted + missed, expected, 1.0) << s.dump(2);
  EXPECT_LT(missed, expected * 0.25) << "the field thread is far behind its schedule\n" << s.dump(2);
  EXPECT_GT(s.at("frames_rendered").get<int>(), 0);
  EXPECT_EQ(s.at("sinks_dropped").get<int>(), 0);
  // Every output frame is in the file, a missed field repeated in its place so the video keeps
  // time: two fields per interlaced frame (a last lone field is completed at close), 4:2:0 320×240.
  const int frames = y4mFrames(320 * 240 * 3 / 2);
  EXPECT_EQ(frames, (static_cast<int>(emitted + missed) + 1) / 2) << r.output;
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
  // renderer and the warp would leave the two pictures alike.
  const RunResult ahead = run("--config " + config() + " --duration 2");
  ASSERT_EQ(ahead.exitCode, 0) << ahead.output;
  const double aheadLuma = lastFrameLuma(120, 240);
  const RunResult up = run("--config " + config("[view]\noffset_deg = [0, 90, 0]\n") + " --duration 2");
  ASSERT_EQ(up.exitCode, 0) << up.output;
  const double upLuma = lastFrameLuma(120, 240);
  EXPECT_GT(upLuma, aheadLuma + 40.0) << "ahead " << aheadLuma << ", up " << upLuma;
  EXPECT_EQ(summary().at("fields_black").get<int>(), 0);
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
