// fieldcast-bench — the end-to-end benchmark of the service: the real render loop, field loop
// and sinks, run in-process for a few seconds per case on a scripted flight, then one table of
// what matters to an integrator: render rate, fields missed, field-time jitter, warp cost and
// frame age. Each case runs `--repeat` times and the table shows medians; the first case is the
// baseline the others are compared with (same machine, same run).
#include <service/Service.h>
#include <service/ServiceConfig.h>

#include <fieldcast/ToolMain.h>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace {

using fieldcast::app::ServiceFigures;

struct Case {
  std::string name;
  std::vector<std::string> overrides;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

ServiceFigures runCase(const std::string& configPath, const Case& c, const std::vector<std::string>& common) {
  std::vector<std::string> overrides = common;
  overrides.insert(overrides.end(), c.overrides.begin(), c.overrides.end());
  const auto config = fieldcast::app::loadServiceConfig(configPath, overrides);
  fieldcast::app::Service service(config);
  service.start();
  while (service.running()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  if (const std::string fatal = service.fatalError(); !fatal.empty()) throw std::runtime_error(fatal);
  return service.stop();
}

int run(int argc, char** argv) {
  CLI::App cli{"fieldcast-bench: end-to-end figures of the service on a scripted flight", "fieldcast-bench"};
  std::string configPath = FIELDCAST_DEFAULT_CONFIG;
  std::string flight = FIELDCAST_DEFAULT_FLIGHT;
  double seconds = 10.0;
  int repeat = 3;
  std::vector<std::string> extra;
  cli.add_option("-c,--config", configPath, "Service configuration")->capture_default_str();
  cli.add_option("--flight", flight, "Scripted flight")->capture_default_str();
  cli.add_option("--seconds", seconds, "Video seconds per run")->capture_default_str();
  cli.add_option("--repeat", repeat, "Runs per case (medians are reported)")->capture_default_str();
  cli.add_option("--set", extra, "Extra override for every case (repeatable)");
  CLI11_PARSE(cli, argc, argv);
  spdlog::set_level(spdlog::level::warn);

  // Outputs go to a shared-memory ring only: the bench measures the pipeline, not the disk.
  std::vector<std::string> common = {
      "motion.source=\"flight\"", "motion.flight=\"" + flight + "\"", "motion.duration_s=" + std::to_string(seconds),
      "sinks.y4m.enabled=false",  "sinks.shm.enabled=true",           "sinks.shm.name=\"/fieldcast_bench\"",
      "metrics.summary_json=\"\""};
  common.insert(common.end(), extra.begin(), extra.end());
  const std::vector<Case> cases = {
      {"hold, IG free-running (baseline)", {"warp.kind=\"hold\""}},
      {"quadratic, IG free-running", {"warp.kind=\"quadratic\""}},
      {"homography, IG free-running", {"warp.kind=\"homography\""}},
      {"quadratic, IG capped at 10 Hz", {"warp.kind=\"quadratic\"", "render.max_rate_hz=10"}},
      {"quadratic, one render worker", {"warp.kind=\"quadratic\"", "render.threads=1"}},
      // The frame-time controller holding a render period of 10 ms (100 Hz): the quality
      // column shows how far it coarsened to do it.
      {"quadratic, controller at 10 ms", {"warp.kind=\"quadratic\"", "render.target_frame_ms=10"}},
  };

  std::printf("fieldcast-bench: %s, %.0f s per run, %d runs per case (medians)\n", flight.c_str(), seconds, repeat);
  std::printf("%-34s %9s %8s %7s %9s %9s %9s %9s %9s %9s %8s\n", "case", "render Hz", "fields", "missed", "warp p50",
              "warp p99", "ratio", "jit p99", "jit max", "age p50", "quality");
  double baselineWarp = 0.0;
  for (const Case& c : cases) {
    std::vector<double> hz, fields, missed, warp50, warp99, jitter99, jitterMax, age50, quality;
    for (int r = 0; r < repeat; ++r) {
      const ServiceFigures f = runCase(configPath, c, common);
      hz.push_back(static_cast<double>(f.framesRendered) / std::max(1e-9, f.durationS));
      fields.push_back(static_cast<double>(f.fieldsEmitted));
      missed.push_back(static_cast<double>(f.fieldsMissed));
      warp50.push_back(f.warp.p50S * 1e3);
      warp99.push_back(f.warp.p99S * 1e3);
      jitter99.push_back(f.jitter.p99S * 1e3);
      jitterMax.push_back(f.jitter.maxS * 1e3);
      age50.push_back(f.frameAge.p50S * 1e3);
      quality.push_back(f.meanQuality);
    }
    if (baselineWarp == 0.0) baselineWarp = median(warp50);
    std::printf("%-34s %9.1f %8.0f %7.0f %7.2fms %7.2fms %8.2fx %7.2fms %7.2fms %7.1fms %8.2f\n", c.name.c_str(),
                median(hz), median(fields), median(missed), median(warp50), median(warp99),
                median(warp50) / baselineWarp, median(jitter99), median(jitterMax), median(age50), median(quality));
    std::fflush(stdout);
  }
  std::printf(
      "warp = field thread's work per field (warp, post-processing, hand-off); ratio = warp p50 / baseline;\n"
      "jit = field wake-up lateness; age = field display time - pose time of its frame;\n"
      "quality = mean quality knob of the frames (1 = a voxel per pixel; larger is coarser).\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return fieldcast::runProgram("fieldcast-bench", run, argc, argv); }
