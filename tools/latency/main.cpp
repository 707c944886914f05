// fieldcast-latency: the extrapolation-latency test bench. Flies scripted flights in virtual time
// with the IG at several render rates, makes every field with each warp from the newest frame,
// compares it with the truth rendered at the field's own pose, and writes a report folder:
// report.md (tables, the command that made them), CSV files, gnuplot plots and the worst fields.
// See tools/latency/README.md.
#include "Report.h"
#include "ResidentTerrain.h"
#include "WarpEvaluation.h"

#include <ig_core/SyntheticTerrain.h>

#include <fieldcast/ToolMain.h>

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#ifndef FIELDCAST_SOURCE_DIR
#define FIELDCAST_SOURCE_DIR "."
#endif

namespace {

namespace fs = std::filesystem;
using fieldcast::tools::EvaluationSpec;

/// A progress bar on stderr, redrawn in place on a terminal and every 10 % otherwise.
class ProgressBar {
 public:
  explicit ProgressBar(int flights) : mFlights(flights), mTerminal(::isatty(2) != 0) {}

  void update(int flight, const std::string& name, int done, int total) {
    const double fraction = (flight + static_cast<double>(done) / total) / mFlights;
    const int percent = static_cast<int>(100.0 * fraction);
    if (!mTerminal && percent / 10 == mLastDecile) return;
    mLastDecile = percent / 10;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * fraction);
    std::fprintf(stderr, "%s[%.*s%*s] %3d%%  %s (%d/%d)%s", mTerminal ? "\r" : "", filled,
                 "##############################", kWidth - filled, "", percent, name.c_str(), flight + 1, mFlights,
                 mTerminal ? "   " : "\n");
    std::fflush(stderr);
  }
  void finish() {
    if (mTerminal) std::fprintf(stderr, "\n");
  }

 private:
  int mFlights;
  bool mTerminal;
  int mLastDecile = -1;
};

std::string commandLine(int argc, char** argv) {
  std::string s = "fieldcast-latency";
  for (int i = 1; i < argc; ++i) s += std::string(" ") + argv[i];
  return s;
}

int run(int argc, char** argv) {
  CLI::App app{
      "The extrapolation-latency test bench: warp fidelity against the truth over scripted flights, "
      "per IG rate and warp, written as a report with plots"};
  const std::string flights = std::string(FIELDCAST_SOURCE_DIR) + "/config/flights/";
  std::vector<std::string> flightPaths{flights + "eval_climb.toml", flights + "eval_turn30.toml",
                                       flights + "eval_lowpass250.toml", flights + "eval_stick_aggressive.rec"};
  std::vector<double> stickStart{1600.0, 1000.0, 150.0, 0.0};
  double stickSpeedMps = 150.0;
  std::vector<double> rates{5.0, 10.0, 15.0, 20.0, 30.0, 60.0};
  EvaluationSpec spec;
  spec.rasterWidthPx = 720;
  spec.rasterHeightPx = 486;
  int terrainSize = 2048;
  std::string databasePath;
  int databaseBudgetMb = 4096;
  unsigned seed = 1;
  int threads = 0;
  bool quick = false;
  std::string scan = "interlaced";
  std::string outDir = "out/latency";
  std::string plotScript = std::string(FIELDCAST_SOURCE_DIR) + "/tools/latency/plots.gnuplot";
  bool exactOnly = false;
  bool noEndToEnd = false;
  int steps = 40;
  // The service: built beside this tool (build/app/fieldcast next to build/tools/latency/)
  std::string fieldcastExe =
      (fs::read_symlink("/proc/self/exe").parent_path() / "../../app/fieldcast").lexically_normal();
  spec.fieldPoses = {fieldcast::tools::FieldPoses::Exact, fieldcast::tools::FieldPoses::HostPredicted};
  app.add_option("--out", outDir, "Report folder (created; files in it are replaced)");
  app.add_flag("--quick", quick, "A short version (seconds): 360x240, 60 fields per flight, IG at 10 and 30 Hz");
  app.add_option("--flight", flightPaths,
                 "Flights: scripted flight files (*.toml) and stick recordings (*.rec, flown by the stick model)")
      ->check(CLI::ExistingFile);
  app.add_option("--stick-start", stickStart,
                 "Start of a stick flight: x,y (m), height above the ground (m), heading (deg)")
      ->delimiter(',')
      ->expected(4);
  app.add_option("--stick-speed", stickSpeedMps, "Airspeed at the start of a stick flight, m/s")
      ->check(CLI::Range(40.0, 300.0));
  app.add_option("--rates", rates, "IG render rates in Hz (render latency = one frame period)")
      ->delimiter(',')
      ->check(CLI::Range(1.0, 240.0));
  app.add_option("--width", spec.rasterWidthPx, "Output raster width (= display window)")->check(CLI::Range(16, 4096));
  app.add_option("--height", spec.rasterHeightPx, "Output raster height")->check(CLI::Range(16, 4096));
  app.add_option("--hfov", spec.hfovDeg, "Horizontal field of view, degrees")->check(CLI::Range(10.0, 120.0));
  app.add_option("--fields", spec.fields, "Fields evaluated per flight and rate")->check(CLI::Range(1, 100000));
  app.add_option("--start", spec.startS, "Flight time of the first field, seconds")->check(CLI::Range(0.2, 3600.0));
  app.add_option("--scan", scan, "interlaced (59.94 Hz fields, bottom first) or progressive")
      ->check(CLI::IsMember({"interlaced", "progressive"}));
  app.add_option("--terrain-size", terrainSize, "Built-in hills: voxels per side (2 m spacing)")
      ->check(CLI::Range(256, 8192));
  app.add_option("--seed", seed, "Built-in hills: noise seed");
  app.add_option("--db", databasePath,
                 "A terrain database (fieldcast-db build) instead of the built-in hills, loaded whole; the "
                 "flights (--flight) must be placed over it");
  app.add_option("--db-budget-mb", databaseBudgetMb, "Memory for the --db database's tiles, MB")
      ->check(CLI::Range(16, 1 << 20));
  app.add_option("--threads", threads, "Render threads (0: one per core); warps always run on one");
  app.add_option("--plot-script", plotScript, "The gnuplot script that draws the plots")->check(CLI::ExistingFile);
  app.add_flag("--exact-only", exactOnly, "Only the exact field poses (no host-predicted poses)");
  app.add_flag("--no-e2e", noEndToEnd, "Do not run the service for the end-to-end input → field latency");
  app.add_option("--e2e-steps", steps, "Step inputs per input (stick, host) in the end-to-end measurement")
      ->check(CLI::Range(1, 1000));
  app.add_option("--fieldcast", fieldcastExe, "The service the end-to-end measurement runs");
  app.add_option("--host-rate", spec.host.rateHz, "Host frames per second (predicted poses)")
      ->check(CLI::Range(10.0, 240.0));
  app.add_option("--host-delay-ms", spec.host.baseDelayMs, "Smallest one-way network delay")
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--host-jitter-ms", spec.host.jitterMs, "Uniform random delay added to each datagram")
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--host-seed", spec.host.seed, "Seed of the network jitter");
  CLI11_PARSE(app, argc, argv);
  if (quick) {
    // Explicit options still win over the quick defaults
    if (app.count("--width") == 0) spec.rasterWidthPx = 360;
    if (app.count("--height") == 0) spec.rasterHeightPx = 240;
    if (app.count("--fields") == 0) spec.fields = 60;
    if (app.count("--rates") == 0) rates = {10.0, 30.0};
    if (app.count("--e2e-steps") == 0) steps = 8;
  }
  spec.scan = scan == "progressive" ? fieldcast::ScanMode::Progressive : fieldcast::ScanMode::Interlaced;
  if (exactOnly) spec.fieldPoses = {fieldcast::tools::FieldPoses::Exact};
  std::sort(rates.begin(), rates.end());
  rates.erase(std::unique(rates.begin(), rates.end()), rates.end());

  const auto started = std::chrono::steady_clock::now();
  // The terrain: the built-in hills in memory, or a database loaded whole
  std::unique_ptr<fieldcast::core::MemoryTerrain> hills;
  std::unique_ptr<fieldcast::core::TileCache> database;
  std::string scene;
  if (databasePath.empty()) {
    hills = fieldcast::core::makeSyntheticTerrain({fieldcast::core::SyntheticKind::Hills, terrainSize, 2.0, 6, seed});
    scene = "Built-in hills, " + std::to_string(terrainSize) + "² voxels at 2 m (seed " + std::to_string(seed) + ")";
  } else {
    std::fprintf(stderr, "loading %s whole (--db-budget-mb %d)\n", databasePath.c_str(), databaseBudgetMb);
    database = fieldcast::tools::openResidentDatabase(databasePath, std::size_t(databaseBudgetMb) << 20);
    const fieldcast::core::TerrainGeometry& g = database->geometry();
    scene = "Database " + fs::path(databasePath).filename().string() + ", " + std::to_string(g.widthVox) + " × " +
            std::to_string(g.heightVox) + " voxels at " + std::to_string(g.spacingM).substr(0, 4) +
            " m, every tile resident";
  }
  const fieldcast::core::TerrainView& terrain = databasePath.empty() ? hills->view() : database->view();
  fieldcast::core::RenderSettings settings;
  settings.rangeImage = true;  // the depth-mesh and 3D warps and the geometric truth need it
  fieldcast::core::Renderer renderer(terrain, settings, threads);

  fieldcast::tools::ReportInput input;
  input.command = commandLine(argc, argv);
  input.scene = scene + ", the renderer at full quality with its range image";
  input.spec = spec;
  input.ratesHz = rates;
  // A stick recording is flown by the service's generic profile and flight model over the hills
  auto stickFlightOver = [&](const std::string& path) {
    fieldcast::Pose start;
    start.positionM = {stickStart[0], stickStart[1], terrain.heightAtM(stickStart[0], stickStart[1]) + stickStart[2]};
    start.headingRad = fieldcast::radians(stickStart[3]);
    return fieldcast::tools::stickFlight(path, start, stickSpeedMps, terrain);
  };
  ProgressBar bar(static_cast<int>(flightPaths.size()));
  for (std::size_t i = 0; i < flightPaths.size(); ++i) {
    const fieldcast::tools::EvaluatedFlight flight = flightPaths[i].ends_with(".rec")
                                                         ? stickFlightOver(flightPaths[i])
                                                         : fieldcast::tools::scriptedFlight(flightPaths[i]);
    fieldcast::tools::FlightResults results;
    results.flight = flight.name();
    if (const auto outside = fieldcast::tools::whereFlightLeavesTerrain(flight, terrain.geometry(), spec)) {
      throw std::runtime_error(*outside + (databasePath.empty() ? " (--terrain-size)" : " (--flight)"));
    }
    results.clearanceM = fieldcast::tools::minimumClearanceM(flight, terrain, spec);
    results.rates = fieldcast::tools::evaluateFlight(flight, renderer, spec, rates, [&](int done, int total) {
      bar.update(static_cast<int>(i), flight.name(), done, total);
    });
    input.flights.push_back(std::move(results));
  }
  bar.finish();
  if (noEndToEnd) {
    input.endToEndSkipped = "--no-e2e";
  } else if (!fs::is_regular_file(fieldcastExe)) {
    input.endToEndSkipped = "the service was not found at " + fieldcastExe + " (--fieldcast)";
  } else {
    for (const auto kind : {fieldcast::tools::EndToEndInput::Stick, fieldcast::tools::EndToEndInput::Host}) {
      std::fprintf(stderr, "end to end: %d %s steps into %s\n", steps, fieldcast::tools::name(kind),
                   fieldcastExe.c_str());
      fieldcast::tools::EndToEndSpec e2e;
      e2e.fieldcastExe = fieldcastExe;
      e2e.workDir = fs::temp_directory_path() / ("fieldcast-latency-e2e-" + std::to_string(::getpid()));
      e2e.input = kind;
      e2e.steps = steps;
      input.endToEnd.push_back(fieldcast::tools::measureInputToField(e2e));
      if (!input.endToEnd.back().problem.empty()) {
        std::fprintf(stderr, "end to end: %s\n", input.endToEnd.back().problem.c_str());
      }
    }
  }
  input.elapsedS = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  const auto plotProblem = fieldcast::tools::writeReport(outDir, input, plotScript);
  std::fprintf(stderr, "report: %s/report.md (%.0f s)\n", outDir.c_str(), input.elapsedS);
  if (plotProblem) {
    std::fprintf(stderr, "fieldcast-latency: %s\n", plotProblem->c_str());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return fieldcast::runProgram("fieldcast-latency", run, argc, argv); }
