// fieldcast — the real-time image generator service.
#include <service/Service.h>
#include <service/ServiceConfig.h>

#include <fieldcast/SimdLevel.h>
#include <fieldcast/ToolMain.h>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

// The CLI's paths are relative to where the user stands; the configuration's to its own folder.
std::string absolute(const std::string& path) {
  return path == "-" ? path : std::filesystem::absolute(path).lexically_normal().string();
}
std::string quoted(const std::string& text) { return "\"" + text + "\""; }

int run(int argc, char** argv) {
  CLI::App cli{
      "fieldcast: a real-time image generator. Renders voxel terrain by ray casting, warps the newest\n"
      "frame to every video field's display time and emits fields at a fixed rate (59.94, 60 or 50 Hz).\n"
      "Runs until SIGINT/SIGTERM (or --duration); every key of the configuration is in config/README.md.\n\n"
      "Examples:\n"
      "  fieldcast --duration 20 --y4m out/flight.y4m --contact-sheet out/sheet.png\n"
      "  fieldcast --set render.max_rate_hz=10 --set warp.kind=hold --summary out/hold.json\n"
      "  fieldcast --set motion.source=stick --set input.stick=/dev/input/event5 --rtp 127.0.0.1:5004",
      "fieldcast"};
  std::string configPath = FIELDCAST_DEFAULT_CONFIG;
  std::vector<std::string> overrides;
  bool checkOnly = false;
  double durationS = 0.0;
  std::string flight, y4m, contactSheet, summary, fieldLog, rtp, simd;
  cli.add_option("-c,--config", configPath, "Configuration file (TOML)")->capture_default_str();
  cli.add_option("--set", overrides, "Override a key: --set output.rate=50 (repeatable)");
  // Whether --duration was given is its count, not a magic value: -1 and NaN used to pass as "not
  // given" and run until killed. NaN fails both comparisons, infinity the upper one.
  CLI::Option* durationOpt =
      cli.add_option("--duration", durationS,
                     "Stop after this many seconds of video, 0 to 1e7; 0 = until SIGINT/SIGTERM (motion.duration_s)")
          ->check(CLI::Validator(
              [](std::string& text) -> std::string {
                double v = 0.0;
                if (CLI::detail::lexical_cast(text, v) && v >= 0.0 && v <= 1e7) return {};
                return "expected a finite number of seconds from 0 to 1e+07 (0 = until SIGINT/SIGTERM), got '" + text +
                       "'";
              },
              "SECONDS"));
  cli.add_option("--flight", flight, "Scripted flight to fly (motion.flight), e.g. config/flights/bank_turn.toml");
  cli.add_option("--y4m", y4m, "Write the fields to this Y4M file, or - for stdout (sinks.y4m)");
  cli.add_option("--contact-sheet", contactSheet, "Write a PNG of fields through the run here at exit");
  cli.add_option("--summary", summary, "Write the run's figures as JSON here at exit (metrics.summary_json)");
  cli.add_option("--field-log", fieldLog, "Write one CSV line per emitted field here (metrics.field_log)");
  cli.add_option("--rtp", rtp, "Send RFC 4175 RTP video to host:port (sinks.rtp)");
  cli.add_option(
      "--simd", simd,
      "SIMD level of the vector kernels: avx512vbmi, avx512, avx2, sse4, ssse3, scalar or auto (the best the "
      "CPU has; also FIELDCAST_SIMD)");
  cli.add_flag("--check-config", checkOnly, "Validate the configuration, print a summary and exit");
  cli.set_version_flag("--version", std::string("fieldcast ") + FIELDCAST_VERSION);
  CLI11_PARSE(cli, argc, argv);
  try {
    fieldcast::applySimdLevelFromEnvironment();
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "fieldcast: FIELDCAST_SIMD: %s\n", e.what());
    return 1;
  }
  try {
    if (!simd.empty()) fieldcast::forceSimdLevel(simd);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "fieldcast: --simd: %s\n", e.what());
    return 1;
  }

  if (durationOpt->count() > 0) {
    char seconds[32];  // every digit: std::to_string would turn 1e-7 into 0, "until killed"
    std::snprintf(seconds, sizeof seconds, "%.17g", durationS);
    overrides.push_back(std::string("motion.duration_s=") + seconds);
  }
  if (!flight.empty()) {
    overrides.push_back("motion.source=\"flight\"");
    overrides.push_back("motion.flight=" + quoted(absolute(flight)));
  }
  if (!y4m.empty()) {
    overrides.push_back("sinks.y4m.enabled=true");
    overrides.push_back("sinks.y4m.path=" + quoted(absolute(y4m)));
  }
  if (!contactSheet.empty()) overrides.push_back("sinks.contact_sheet=" + quoted(absolute(contactSheet)));
  if (!summary.empty()) overrides.push_back("metrics.summary_json=" + quoted(absolute(summary)));
  if (!fieldLog.empty()) overrides.push_back("metrics.field_log=" + quoted(absolute(fieldLog)));
  if (!rtp.empty()) {
    const auto colon = rtp.rfind(':');
    if (colon == std::string::npos) {
      std::fprintf(stderr, "fieldcast: --rtp: expected host:port, got %s\n", rtp.c_str());
      return 1;
    }
    overrides.push_back("sinks.rtp.enabled=true");
    overrides.push_back("sinks.rtp.address=" + quoted(rtp.substr(0, colon)));
    overrides.push_back("sinks.rtp.port=" + rtp.substr(colon + 1));
  }

  fieldcast::app::ServiceConfig config;
  try {
    config = fieldcast::app::loadServiceConfig(configPath, overrides);
  } catch (const fieldcast::app::ConfigError& e) {
    std::fprintf(stderr, "fieldcast: %s\n", e.what());
    return 1;
  }
  if (checkOnly) {
    std::printf("%s\nconfiguration OK\n", fieldcast::app::describe(config).c_str());
    return 0;
  }

  // SIGINT/SIGTERM are taken synchronously by this thread; every other thread blocks them.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  spdlog::info("{}", fieldcast::app::describe(config));
  std::string levels;
  for (const std::string& level : fieldcast::simdLevels()) levels += (levels.empty() ? "" : ", ") + level;
  spdlog::info("SIMD level {} (this CPU runs {})", fieldcast::simdLevel(), levels);
  fieldcast::app::Service service(config);
  service.start();
  const auto interval = fieldcast::fromSeconds(config.metrics.logIntervalS);
  auto nextLog = fieldcast::MonotonicClock::now() + interval;
  while (service.running()) {
    const timespec poll{0, 50'000'000};
    const int got = sigtimedwait(&signals, nullptr, &poll);
    if (got > 0) {
      spdlog::info("{}: stopping", got == SIGINT ? "SIGINT" : "SIGTERM");
      break;
    }
    if (fieldcast::MonotonicClock::now() >= nextLog) {
      spdlog::info("{}", service.intervalLine());
      nextLog += interval;
    }
  }
  const fieldcast::app::ServiceFigures figures = service.stop();
  spdlog::info("{}", fieldcast::app::describe(figures));
  if (const std::string fatal = service.fatalError(); !fatal.empty()) {
    std::fprintf(stderr, "fieldcast: %s\n", fatal.c_str());
    return 1;
  }
  if (!config.metrics.summaryJson.empty()) spdlog::info("summary: {}", config.metrics.summaryJson.string());
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return fieldcast::runProgram("fieldcast", run, argc, argv); }
