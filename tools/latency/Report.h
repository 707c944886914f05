#pragma once
// The report folder of fieldcast-latency: report.md with its tables, the CSV files behind them,
// the gnuplot data and plots, and the worst field of each flight as a picture strip.

#include "EndToEnd.h"
#include "WarpEvaluation.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace fieldcast::tools {

/// Everything measured on one flight.
struct FlightResults {
  std::string flight;
  double clearanceM = 0.0;        ///< minimum height above the terrain along the evaluated part
  std::vector<RateResult> rates;  ///< rate-major (ReportInput::ratesHz), each rate's field poses in the spec's order
};

/// What the report is written from.
struct ReportInput {
  std::string command;  ///< the command line that made it, quoted in the report
  std::string scene;    ///< the terrain, in words
  EvaluationSpec spec;
  std::vector<double> ratesHz;
  std::vector<FlightResults> flights;
  std::vector<EndToEndResult> endToEnd;  ///< the running service's input → field latency, per input measured
  std::string endToEndSkipped;           ///< why it was not, when not
  double elapsedS = 0.0;
};

/// The IG rate a warp needs on a flight, with field poses `poses`, to keep the mean geometric
/// error under `limitPx`: the slowest evaluated rate from which every faster evaluated rate stays
/// under it. Nothing when even the fastest rate does not.
std::optional<double> neededRateHz(const FlightResults& flight, FieldPoses poses, warp::WarpKind kind, double limitPx);

/// Writes the report into `dir` (created if missing): report.md, warps.csv, fields.csv,
/// needed_rate.csv, the worst-field strips (PNG) and the plot data. Then runs gnuplot on
/// `plotScript` to draw the plots; returns gnuplot's complaint, or nothing when the plots were
/// drawn. Throws std::runtime_error when a file cannot be written.
std::optional<std::string> writeReport(const std::filesystem::path& dir, const ReportInput& input,
                                       const std::filesystem::path& plotScript);

}  // namespace fieldcast::tools
