// fieldcast-bench — the end-to-end benchmark of the service: the real render loop, field loop
// and sinks, run in-process for a few seconds per case on a scripted flight, then one table of
// what matters to an integrator: render rate, fields missed, field-time jitter, warp cost and
// frame age. Each case runs `--repeat` times and the table shows medians; the first case is the
// baseline the others are compared with (same machine, same run). The host case drives the
// service from `fieldcast-host` over loopback CIGI (the real path: UDP arrival at the IG → the
// first emitted field whose pose uses that sample) and prints its latency beside the field period
// and the warp time of the same run.
#include <service/Service.h>
#include <service/ServiceConfig.h>

#include <fieldcast/ToolMain.h>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <stdexcept>
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

// A UDP port nobody uses now (bound, read back, released), for the host case's link.
int freeUdpPort() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof a;
  const bool ok = fd >= 0 && ::bind(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0 &&
                  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &length) == 0;
  if (fd >= 0) ::close(fd);
  if (!ok) throw std::runtime_error("host case: no free UDP port on 127.0.0.1");
  return ntohs(a.sin_port);
}

// The host case: the service with motion.source = "host" runs in-process while `fieldcast-host`
// flies `flight` at it for `seconds` at 60 Hz; the service runs until the host is done.
ServiceFigures runHostCase(const std::string& configPath, const std::string& hostExe, const std::string& flight,
                           double seconds, const std::vector<std::string>& common) {
  const int port = freeUdpPort();
  std::vector<std::string> overrides = common;
  overrides.insert(overrides.end(),
                   {"motion.source=\"host\"", "motion.duration_s=0", "host.port=" + std::to_string(port)});
  const auto config = fieldcast::app::loadServiceConfig(configPath, overrides);
  fieldcast::app::Service service(config);
  service.start();
  const std::string command = hostExe + " --config '" + configPath + "' --flight '" + flight + "' --ig-port " +
                              std::to_string(port) + " --rate 60 --duration " + std::to_string(seconds) +
                              " --wait-for-ig 30 2>&1";
  std::string output;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("host case: cannot run " + hostExe);
  std::array<char, 1024> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe)) output += buffer.data();
  const int status = pclose(pipe);
  const ServiceFigures figures = service.stop();
  if (const std::string fatal = service.fatalError(); !fatal.empty()) throw std::runtime_error(fatal);
  if (status != 0) throw std::runtime_error("host case: " + command + " failed:\n" + output);
  return figures;
}

int run(int argc, char** argv) {
  CLI::App cli{"fieldcast-bench: end-to-end figures of the service on a scripted flight", "fieldcast-bench"};
  std::string configPath = FIELDCAST_DEFAULT_CONFIG;
  std::string flight = FIELDCAST_DEFAULT_FLIGHT;
  double seconds = 10.0;
  int repeat = 3;
  std::string only;
  std::string hostExe = FIELDCAST_HOST_EXE;
  std::vector<std::string> extra;
  cli.add_option("-c,--config", configPath, "Service configuration")->capture_default_str();
  cli.add_option("--flight", flight, "Scripted flight")->capture_default_str();
  cli.add_option("--seconds", seconds, "Video seconds per run")->capture_default_str();
  cli.add_option("--repeat", repeat, "Runs per case (medians are reported)")->capture_default_str();
  cli.add_option("--set", extra, "Extra override for every case (repeatable)");
  cli.add_option("--only", only, "Run only the cases whose name contains this (\"host\": the host case)");
  cli.add_option("--host-exe", hostExe, "fieldcast-host, for the host case")->capture_default_str();
  CLI11_PARSE(cli, argc, argv);
  spdlog::set_level(spdlog::level::warn);

  // Outputs go to a shared-memory ring only: the bench measures the pipeline, not the disk.
  std::vector<std::string> common = {
      "motion.source=\"flight\"", "motion.flight=\"" + flight + "\"", "motion.duration_s=" + std::to_string(seconds),
      "sinks.y4m.enabled=false",  "sinks.shm.enabled=true",           "sinks.shm.name=\"/fieldcast_bench\"",
      "metrics.summary_json=\"\""};
  common.insert(common.end(), extra.begin(), extra.end());
  const auto selected = [&](const std::string& name) { return only.empty() || name.find(only) != std::string::npos; };
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
  const bool anyTable = std::any_of(cases.begin(), cases.end(), [&](const Case& c) { return selected(c.name); });
  if (anyTable)
    std::printf("%-34s %9s %8s %7s %9s %9s %9s %9s %9s %9s %8s\n", "case", "render Hz", "fields", "missed", "warp p50",
                "warp p99", "ratio", "jit p99", "jit max", "age p50", "quality");
  double baselineWarp = 0.0;
  for (const Case& c : cases) {
    if (!selected(c.name)) continue;
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
  if (anyTable) {
    std::printf(
        "warp = field thread's work per field (warp, post-processing, hand-off); ratio = warp p50 / baseline;\n"
        "jit = field wake-up lateness; age = field display time - pose time of its frame;\n"
        "quality = mean quality knob of the frames (1 = a voxel per pixel; larger is coarser).\n");
  }

  const std::string hostCase = "host: fieldcast-host at 60 Hz";
  if (!selected(hostCase)) return 0;
  std::printf("\n%-42s %7s %7s %8s %9s %9s %9s %9s %9s %9s %9s\n", "case", "fields", "missed", "period", "warp p50",
              "warp p99", "emit p50", "emit p99", "disp p50", "disp p99", "aim");
  std::vector<double> fields, missed, warp50, warp99, emit50, emit99, disp50, disp99, samples;
  for (int r = 0; r < repeat; ++r) {
    const ServiceFigures f = runHostCase(configPath, hostExe, flight, seconds, common);
    fields.push_back(static_cast<double>(f.fieldsEmitted));
    missed.push_back(static_cast<double>(f.fieldsMissed));
    warp50.push_back(f.warp.p50S * 1e3);
    warp99.push_back(f.warp.p99S * 1e3);
    emit50.push_back(f.hostToEmission.p50S * 1e3);
    emit99.push_back(f.hostToEmission.p99S * 1e3);
    disp50.push_back(f.hostToDisplay.p50S * 1e3);
    disp99.push_back(f.hostToDisplay.p99S * 1e3);
    samples.push_back(static_cast<double>(f.hostToEmission.count));
  }
  const auto config = fieldcast::app::loadServiceConfig(configPath, common);
  const double periodMs = fieldcast::toSeconds(config.output.fieldRate.period()) * 1e3;
  std::printf("%-42s %7.0f %7.0f %6.2fms %7.2fms %7.2fms %7.2fms %7.2fms %7.2fms %7.2fms %7.2fms\n", hostCase.c_str(),
              median(fields), median(missed), periodMs, median(warp50), median(warp99), median(emit50), median(emit99),
              median(disp50), median(disp99), periodMs + median(warp99));
  std::printf(
      "emit / disp = host datagram arrival at the IG -> emission / display time of the first field whose pose\n"
      "uses its sample (%.0f samples per run); aim = p99 emit <= one field period + warp p99.\n",
      median(samples));
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return fieldcast::runProgram("fieldcast-bench", run, argc, argv); }
