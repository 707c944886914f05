// fieldcast-warpeval: how well each warp extrapolates frames to fields, over scripted flights in
// virtual time. Prints one table row per flight, render rate and warp: PSNR against the ground
// truth rendered at every field's own pose, and the geometric error of the warp's sampling map at
// held-out check pixels. See prp_warp/README.md for the method and figures.
#include "WarpEvaluation.h"

#include <ig_core/SyntheticTerrain.h>

#include <fieldcast/ToolMain.h>

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#ifndef FIELDCAST_SOURCE_DIR
#define FIELDCAST_SOURCE_DIR "."
#endif

namespace {

using fieldcast::tools::EvaluationSpec;
using fieldcast::tools::RateResult;

int run(int argc, char** argv) {
  CLI::App app{"Warp quality over scripted flights: hold, quadratic, homography and 3D warp against the truth"};
  const std::string flights = std::string(FIELDCAST_SOURCE_DIR) + "/config/flights/";
  std::vector<std::string> flightPaths{flights + "eval_climb.toml", flights + "eval_turn30.toml",
                                       flights + "eval_lowpass250.toml"};
  std::vector<double> rates{10.0, 15.0, 30.0};
  EvaluationSpec spec;
  int terrainSize = 2048;
  unsigned seed = 1;
  int threads = 0;
  std::string scan = "interlaced";
  std::string csvPath;
  app.add_option("--flight", flightPaths, "Flight files (config/flights/*.toml)")->check(CLI::ExistingFile);
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
  app.add_option("--threads", threads, "Render threads (0: one per core)");
  app.add_option("--csv", csvPath, "Also write the table as CSV to this file");
  CLI11_PARSE(app, argc, argv);
  spec.scan = scan == "progressive" ? fieldcast::ScanMode::Progressive : fieldcast::ScanMode::Interlaced;

  const auto built = std::chrono::steady_clock::now();
  const auto terrain =
      fieldcast::core::makeSyntheticTerrain({fieldcast::core::SyntheticKind::Hills, terrainSize, 2.0, 6, seed});
  fieldcast::core::RenderSettings settings;
  settings.rangeImage = true;  // the 3D warp and the geometric truth need it
  fieldcast::core::Renderer renderer(terrain->view(), settings, threads);
  std::fprintf(stderr, "terrain: hills %d² voxels at 2 m, seed %u (%.1f s); raster %dx%d %s, %d fields per run\n",
               terrainSize, seed, std::chrono::duration<double>(std::chrono::steady_clock::now() - built).count(),
               spec.rasterWidthPx, spec.rasterHeightPx, scan.c_str(), spec.fields);

  std::vector<RateResult> all;
  for (const std::string& path : flightPaths) {
    const auto flight = fieldcast::motion::ScriptedTrajectory::load(path);
    const double clearance = fieldcast::tools::minimumClearanceM(flight, terrain->view(), spec);
    std::fprintf(stderr, "%s: minimum terrain clearance %.0f m\n", flight.name().c_str(), clearance);
    const auto started = std::chrono::steady_clock::now();
    auto results = fieldcast::tools::evaluateFlight(flight, renderer, spec, rates);
    std::fprintf(stderr, "%s: evaluated in %.1f s\n", flight.name().c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    all.insert(all.end(), results.begin(), results.end());
  }

  std::printf("%-22s %6s %7s  %-10s %8s %8s %9s %8s %8s %10s %6s %8s\n", "flight", "IG Hz", "age ms", "warp", "PSNR dB",
              "min dB", "err px", "p95 px", "max px", "viol/fld", "fallbk", "cost ms");
  for (const RateResult& r : all) {
    for (const auto& w : r.warps) {
      std::printf("%-22s %6.1f %7.1f  %-10s %8.2f %8.2f %9.3f %8.3f %8.2f %10.1f %6llu %8.3f\n", r.flight.c_str(),
                  r.renderRateHz, r.meanFrameAgeMs, std::string(fieldcast::warp::toString(w.kind)).c_str(),
                  w.meanPsnrDb, w.minPsnrDb, w.meanErrPx, w.p95ErrPx, w.maxErrPx, w.violationsPerField,
                  static_cast<unsigned long long>(w.fallbacks), w.medianCostMs);
    }
  }
  if (!csvPath.empty()) {
    std::ofstream csv(csvPath);
    if (!csv) throw std::runtime_error(csvPath + ": cannot open for writing");
    csv << "flight,render_hz,mean_age_ms,warp,psnr_db,min_psnr_db,err_px,p95_err_px,max_err_px,violations_per_field,"
           "fallbacks,median_cost_ms\n";
    for (const RateResult& r : all)
      for (const auto& w : r.warps)
        csv << r.flight << ',' << r.renderRateHz << ',' << r.meanFrameAgeMs << ',' << fieldcast::warp::toString(w.kind)
            << ',' << w.meanPsnrDb << ',' << w.minPsnrDb << ',' << w.meanErrPx << ',' << w.p95ErrPx << ',' << w.maxErrPx
            << ',' << w.violationsPerField << ',' << w.fallbacks << ',' << w.medianCostMs << '\n';
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return fieldcast::runProgram("fieldcast-warpeval", run, argc, argv); }
