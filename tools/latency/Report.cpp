// The report folder. Tables are written from the same numbers as the CSV files, so what the
// report says and what a reader can re-plot are one thing. Plots are drawn by gnuplot from
// plain data files (plots/*.dat, one block per flight and warp) so they can be redrawn or
// restyled without re-running the evaluation.
#include "Report.h"

#include <OpenImageIO/imageio.h>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace fieldcast::tools {
namespace {

namespace fs = std::filesystem;

std::ofstream openOut(const fs::path& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path.string() + ": cannot open for writing");
  return out;
}

std::string fixed(double v, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

std::string name(warp::WarpKind kind) { return std::string(warp::toString(kind)); }

/// A flight's name as one word (gnuplot splits its lists on blanks; file names too).
std::string oneWord(std::string s) {
  for (char& c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) c = '_';
  return s;
}

const WarpScore* scoreOf(const RateResult& r, warp::WarpKind kind) {
  for (const WarpScore& w : r.warps)
    if (w.kind == kind) return &w;
  return nullptr;
}

/// The exact-pose result whose figures stand for a flight in the cost plot: 10 Hz when
/// evaluated, else the slowest rate. Null when the run had no exact poses.
const RateResult* referenceRate(const FlightResults& f) {
  const RateResult* slowest = nullptr;
  for (const RateResult& r : f.rates) {
    if (r.poses != FieldPoses::Exact) continue;
    if (std::abs(r.renderRateHz - 10.0) < 1e-9) return &r;
    if (slowest == nullptr || r.renderRateHz < slowest->renderRateHz) slowest = &r;
  }
  return slowest;
}

/// The slowest rate's result with exact poses (the worst-field strips come from it).
const RateResult* slowestExact(const FlightResults& f) {
  const RateResult* slowest = nullptr;
  for (const RateResult& r : f.rates)
    if (r.poses == FieldPoses::Exact && (slowest == nullptr || r.renderRateHz < slowest->renderRateHz)) slowest = &r;
  return slowest;
}

bool evaluated(const ReportInput& in, FieldPoses poses) {
  return std::find(in.spec.fieldPoses.begin(), in.spec.fieldPoses.end(), poses) != in.spec.fieldPoses.end();
}

/// The q-quantile (nearest rank) of `v`; 0 when empty.
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)))];
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

/// The median of a warp's per-rate median costs over the whole run.
double runCostMs(const ReportInput& in, warp::WarpKind kind) {
  std::vector<double> costs;
  for (const FlightResults& f : in.flights)
    for (const RateResult& r : f.rates)
      if (const WarpScore* w = scoreOf(r, kind)) costs.push_back(w->medianCostMs);
  return median(costs);
}

void writeCsvFiles(const fs::path& dir, const ReportInput& in) {
  std::ofstream warps = openOut(dir / "warps.csv");
  warps << "flight,render_hz,poses,mean_age_ms,warp,psnr_db,min_psnr_db,err_px,p95_err_px,max_err_px,"
           "violations_per_field,fallbacks,median_cost_ms\n";
  std::ofstream fields = openOut(dir / "fields.csv");
  fields << "flight,render_hz,poses,field,warp,age_ms,psnr_db,err_px\n";
  for (const FlightResults& f : in.flights)
    for (const RateResult& r : f.rates)
      for (const WarpScore& w : r.warps) {
        warps << f.flight << ',' << r.renderRateHz << ',' << toString(r.poses) << ',' << r.meanFrameAgeMs << ','
              << name(w.kind) << ',' << w.meanPsnrDb << ',' << w.minPsnrDb << ',' << w.meanErrPx << ',' << w.p95ErrPx
              << ',' << w.maxErrPx << ',' << w.violationsPerField << ',' << w.fallbacks << ',' << w.medianCostMs
              << '\n';
        for (std::size_t k = 0; k < w.fields.size(); ++k) {
          const FieldScore& s = w.fields[k];
          fields << f.flight << ',' << r.renderRateHz << ',' << toString(r.poses) << ',' << k << ',' << name(w.kind)
                 << ',' << s.ageMs << ',' << s.psnrDb << ',' << s.meanErrPx << '\n';
        }
      }
  std::ofstream needed = openOut(dir / "needed_rate.csv");
  needed << "flight,poses,warp,needed_hz\n";
  for (const FlightResults& f : in.flights)
    for (FieldPoses poses : in.spec.fieldPoses)
      for (warp::WarpKind kind : kEvaluatedWarps) {
        const auto hz = neededRateHz(f, poses, kind, 1.0);
        needed << f.flight << ',' << toString(poses) << ',' << name(kind) << ','
               << (hz ? fixed(*hz, 1) : std::string("none")) << '\n';
      }
}

/// gnuplot data: one block (two blank lines apart) per flight and warp, in flight-major order.
void writePlotData(const fs::path& dir, const ReportInput& in) {
  std::ofstream rates = openOut(dir / "rates.dat");
  std::ofstream fields = openOut(dir / "fields.dat");
  std::ofstream cost = openOut(dir / "cost.dat");
  rates << "# render_hz mean_age_ms psnr_db err_px p95_err_px median_cost_ms\n";
  fields << "# age_ms err_px psnr_db\n";
  cost << "# median_cost_ms err_px psnr_db warp  (one block per flight, exact poses, at 10 Hz or the slowest rate)\n";
  rates << "# exact field poses only\n";
  for (const FlightResults& f : in.flights) {
    for (warp::WarpKind kind : kEvaluatedWarps) {
      for (const RateResult& r : f.rates) {
        const WarpScore* w = scoreOf(r, kind);
        if (w == nullptr || r.poses != FieldPoses::Exact) continue;
        rates << r.renderRateHz << ' ' << r.meanFrameAgeMs << ' ' << w->meanPsnrDb << ' ' << w->meanErrPx << ' '
              << w->p95ErrPx << ' ' << w->medianCostMs << '\n';
        for (const FieldScore& s : w->fields) fields << s.ageMs << ' ' << s.meanErrPx << ' ' << s.psnrDb << '\n';
      }
      rates << "\n\n";
      fields << "\n\n";
    }
    if (const RateResult* r = referenceRate(f))
      for (warp::WarpKind kind : kEvaluatedWarps)
        if (const WarpScore* w = scoreOf(*r, kind))
          cost << w->medianCostMs << ' ' << w->meanErrPx << ' ' << w->meanPsnrDb << ' ' << name(kind) << '\n';
    cost << "\n\n";
  }
  for (const EndToEndResult& e : in.endToEnd) {
    std::ofstream e2e = openOut(dir / ("e2e_" + std::string(name(e.input)) + ".dat"));
    e2e << "# " << name(e.input) << " → field latency, ms: block 0 the pose, block 1 the pixels\n";
    for (double ms : e.toPoseMs) e2e << ms << '\n';
    e2e << "\n\n";
    for (double ms : e.toPixelsMs) e2e << ms << '\n';
  }
}

/// truth | warped | |difference| × 4, the field's rows shown at the frame's aspect, at most
/// 240 pixels a picture wide (the example report in the repository stays small).
void writeStrip(const fs::path& path, const WorstField& worst, bool interlaced) {
  const Image& a = worst.truth;
  const Image& b = worst.warped;
  const int channels = a.format() == PixelFormat::Rgb8 ? 3 : 1;
  const int step = (a.widthPx() + 239) / 240;  // columns per output pixel
  const int w = a.widthPx() / step;
  const double rowsPerOut = interlaced ? step / 2.0 : step;  // a field row is two raster rows
  const int h = static_cast<int>(a.heightPx() / rowsPerOut);
  const int gap = 4;
  const int stripW = 3 * w + 2 * gap;
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(stripW) * h * 3, 255);
  for (int y = 0; y < h; ++y) {
    const int sy = std::min(a.heightPx() - 1, static_cast<int>(y * rowsPerOut));
    for (int x = 0; x < w; ++x) {
      const std::uint8_t* pa = a.row(sy) + static_cast<std::ptrdiff_t>(x * step * channels);
      const std::uint8_t* pb = b.row(sy) + static_cast<std::ptrdiff_t>(x * step * channels);
      int diff = 0;
      for (int c = 0; c < channels; ++c) diff = std::max(diff, std::abs(pa[c] - pb[c]));
      for (int c = 0; c < 3; ++c) {
        const int cc = std::min(c, channels - 1);
        const auto base = (static_cast<std::size_t>(y) * stripW + x) * 3 + c;
        rgb[base] = pa[cc];
        rgb[base + static_cast<std::size_t>(w + gap) * 3] = pb[cc];
        rgb[base + static_cast<std::size_t>(2 * (w + gap)) * 3] = static_cast<std::uint8_t>(std::min(255, 4 * diff));
      }
    }
  }
  auto out = OIIO::ImageOutput::create(path.string());
  const OIIO::ImageSpec spec(stripW, h, 3, OIIO::TypeDesc::UINT8);
  if (!out || !out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) ||
      !out->close()) {
    throw std::runtime_error(path.string() + ": cannot write the strip: " + OIIO::geterror());
  }
}

/// Runs gnuplot on the script with the report's lists; its output goes to plots/gnuplot.log.
std::optional<std::string> drawPlots(const fs::path& dir, const ReportInput& in, const fs::path& script) {
  std::string flights, warps;
  for (const FlightResults& f : in.flights) {
    if (!flights.empty()) flights += ' ';
    flights += oneWord(f.flight);
  }
  for (warp::WarpKind kind : kEvaluatedWarps) {
    if (!warps.empty()) warps += ' ';
    warps += name(kind);
  }
  // The inputs measured, and those of them seen in the pixels too (gnuplot plots no empty block)
  std::string e2e, e2ePixels;
  for (const EndToEndResult& e : in.endToEnd) {
    if (e.toPoseMs.empty()) continue;
    e2e += std::string(e2e.empty() ? "" : " ") + name(e.input);
    if (!e.toPixelsMs.empty()) e2ePixels += std::string(e2ePixels.empty() ? "" : " ") + name(e.input);
  }
  const std::string settings = "dir='" + (dir / "plots").string() + "'; out='" + dir.string() + "'; flights='" +
                               flights + "'; warps='" + warps + "'; e2e='" + e2e + "'; e2ePixels='" + e2ePixels + "'";
  const fs::path log = dir / "plots" / "gnuplot.log";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::string program = "gnuplot", e = "-e", scriptPath = script.string();
  char* argv[] = {program.data(), e.data(), const_cast<char*>(settings.c_str()), scriptPath.data(), nullptr};
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return "gnuplot could not be started (install gnuplot-nox: scripts/install-deps.sh)";
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return std::nullopt;
  std::ifstream logText(log);
  std::stringstream text;
  text << logText.rdbuf();
  return "gnuplot failed (" + log.string() + "):\n" + text.str();
}

void writeMarkdown(const fs::path& dir, const ReportInput& in, const std::optional<std::string>& plotProblem) {
  std::ofstream md = openOut(dir / "report.md");
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  const EvaluationSpec& spec = in.spec;
  md << "# Extrapolation-latency report\n\n"
     << "Made by `" << in.command << "` on " << date << " in " << fixed(in.elapsedS, 0) << " s on "
     << ::sysconf(_SC_NPROCESSORS_ONLN) << " cores. Every table and plot below comes from this run.\n\n"
     << "**Method.** " << in.scene << ". Output raster " << spec.rasterWidthPx << " × " << spec.rasterHeightPx << ' '
     << (spec.scan == ScanMode::Interlaced ? "interlaced" : "progressive") << " at " << fixed(spec.fieldRate.hz(), 2)
     << " fields/s, horizontal field of view " << fixed(spec.hfovDeg, 0) << "°, " << spec.fields
     << " fields per flight from t = " << fixed(spec.startS, 1)
     << " s. At each IG rate R the IG starts a frame every 1/R s for the flight's pose at that "
        "instant and finishes it one period later (render latency = one frame period); every field "
        "is made by each warp from the newest finished frame, to the field's pose (the flight's "
        "exact pose at the field's display time, or the one predicted from host samples: *poses* "
        "below), and compared with the truth: the same renderer's frame rendered at the exact "
        "pose. PSNR is over the field's pixels; the geometric error is the distance, in frame "
        "pixels, between where the warp sampled and where the truth's surface point lies in the "
        "source frame, at "
     << spec.checkColumns * spec.checkRows
     << " held-out pixels per field (off the nine control points). Warp cost is the warp's own "
        "time per field on one core (median).\n\n";

  // The finding
  md << "## The IG rate each warp needs for a mean error under one pixel\n\n"
     << "The slowest evaluated IG rate from which every faster one keeps the mean geometric error "
        "under 1 px (from `needed_rate.csv`; evaluated rates: ";
  for (std::size_t i = 0; i < in.ratesHz.size(); ++i) md << (i ? ", " : "") << fixed(in.ratesHz[i], 0);
  md << " Hz). *exact*: each field warped to the flight's own pose at its display time (the warps "
        "alone); *host*: to the pose the service's predictor makes from host samples (below).\n\n"
        "| flight | poses |";
  for (warp::WarpKind kind : kEvaluatedWarps) md << ' ' << name(kind) << " |";
  md << "\n| --- | --- |";
  for (std::size_t i = 0; i < kEvaluatedWarps.size(); ++i) md << " ---: |";
  md << '\n';
  for (const FlightResults& f : in.flights) {
    for (FieldPoses poses : in.spec.fieldPoses) {
      md << "| " << f.flight << " | " << toString(poses) << " |";
      for (warp::WarpKind kind : kEvaluatedWarps) {
        const auto hz = neededRateHz(f, poses, kind, 1.0);
        md << ' ' << (hz ? fixed(*hz, 0) + " Hz" : "> " + fixed(in.ratesHz.back(), 0) + " Hz") << " |";
      }
      md << '\n';
    }
  }

  if (evaluated(in, FieldPoses::HostPredicted)) {
    const HostFeed& h = spec.host;
    md << "\n## Pose prediction from a host\n\n"
       << "The flight sampled by a CIGI host at " << fixed(h.rateHz, 0)
       << " Hz (Entity Control with Rate Control's rates), each datagram delayed by " << fixed(h.baseDelayMs, 1)
       << " ms plus a uniform random " << fixed(h.jitterMs, 1) << " ms (seed " << h.seed
       << "), received in arrival order by the service's own predictor "
       << "(`motion::HostMotion`: host clock estimate, Hermite interpolation, extrapolation from the "
          "newest sample's rates), asked for each field's pose "
       << fixed(h.fieldLeadMs, 1)
       << " ms before its display time with the samples that had arrived by then. Error of those poses "
          "against the flight's own (every rate's fields have the same poses):\n\n"
          "| flight | position mean m | position max m | attitude mean ° | attitude max ° |\n"
          "| --- | ---: | ---: | ---: | ---: |\n";
    for (const FlightResults& f : in.flights)
      for (const RateResult& r : f.rates)
        if (r.poses == FieldPoses::HostPredicted) {
          md << "| " << f.flight << " | " << fixed(r.meanPoseError.positionM, 3) << " | "
             << fixed(r.maxPoseError.positionM, 3) << " | " << fixed(r.meanPoseError.angleDeg, 4) << " | "
             << fixed(r.maxPoseError.angleDeg, 4) << " |\n";
          break;
        }
  }

  // Cost
  const double quadraticMs = runCostMs(in, warp::WarpKind::Quadratic);
  md << "\n## Warp cost per field\n\nMedian over the run of each warp's per-flight-and-rate median (one "
        "core, this machine).\n\n| warp | ms per field | × quadratic |\n| --- | ---: | ---: |\n";
  for (warp::WarpKind kind : kEvaluatedWarps) {
    const double ms = runCostMs(in, kind);
    md << "| " << name(kind) << " | " << fixed(ms, 3) << " | "
       << (quadraticMs > 0.0 ? fixed(ms / quadraticMs, 2) : std::string("—")) << " |\n";
  }

  // End to end
  md << "\n## Input → field, end to end, in the running service\n\n";
  if (in.endToEnd.empty()) {
    md << "Not measured: " << in.endToEndSkipped << "\n";
  } else {
    md << "`fieldcast` ran as a user runs it (its own process and clock, 720 × 486 interlaced output, "
          "Y4M and field log on) on a 1 km built-in terrain, once per input:\n\n"
          "- *stick*: a HID device behind a UNIX socket (`hidsocket:`, read by the hidraw source's loop), "
          "thrown fully right or left (alternately) after 0.35 s centred; the instant is taken just "
          "before its report leaves. The pose shows it when the roll moves; the pixels when the left "
          "side's vertical shift minus the right side's does.\n"
          "- *host*: a CIGI host on 127.0.0.1 (`[motion] source = \"host\"`) holding the ownship still "
          "with 60 Hz host frames, its heading stepped by 10° (there and back, alternately) every "
          "0.5 s; the instant is taken just before the first datagram with the new heading leaves. The "
          "pose shows it when the heading moves; the pixels when the mean luma difference does.\n\n"
          "Instants on CLOCK_MONOTONIC, to the emission of the first field that shows the step (handed "
          "to the outputs). A pixel signal is taken against the field two before (same parity), and a "
          "field shows the step when its signal leaves what it was in the 300 ms before by more than "
          "one (row, grey level) and four of its standard deviations. A step not seen within 300 ms "
          "is counted as not found.\n\n"
          "| input | found in | steps found | p50 ms | p99 ms | max ms |\n"
          "| --- | --- | ---: | ---: | ---: | ---: |\n";
    for (const EndToEndResult& e : in.endToEnd) {
      if (!e.problem.empty()) {
        md << "| " << name(e.input) << " | not measured: " << e.problem.substr(0, e.problem.find('\n'))
           << " | | | | |\n";
        continue;
      }
      auto row = [&](const char* what, const std::vector<double>& ms) {
        md << "| " << name(e.input) << " | " << what << " | " << ms.size() << " of " << e.steps << " | "
           << fixed(quantile(ms, 0.5), 1) << " | " << fixed(quantile(ms, 0.99), 1) << " | "
           << fixed(ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end()), 1) << " |\n";
      };
      row("pose", e.toPoseMs);
      row("pixels", e.toPixelsMs);
    }
    const bool plotted = std::any_of(in.endToEnd.begin(), in.endToEnd.end(),
                                     [](const EndToEndResult& e) { return !e.toPoseMs.empty(); });
    if (!plotProblem && plotted) md << "\n![Input to field latency histograms](e2e_latency.png)\n";
  }

  // Plots and strips
  md << "\n## Plots\n\n";
  if (plotProblem) {
    md << "The plots could not be drawn: " << *plotProblem << "\n\n";
  } else {
    md << "![PSNR against IG rate, one panel per flight](psnr_vs_rate.png)\n\n"
       << "![Geometric error against frame age, every field](error_vs_age.png)\n\n"
       << "![Cost against fidelity per warp](cost_vs_fidelity.png)\n\n";
  }
  md << "## The worst field of each flight\n\nAt the slowest IG rate with exact poses, the field with the "
        "lowest PSNR: truth | warped | difference × 4.\n\n";
  for (const FlightResults& f : in.flights) {
    const RateResult* slowestPtr = slowestExact(f);
    if (slowestPtr == nullptr) continue;
    const RateResult& slowest = *slowestPtr;
    for (const WarpScore& w : slowest.warps) {
      if (w.worst.field < 0) continue;
      const std::string file = "worst_" + oneWord(f.flight) + "_" + name(w.kind) + ".png";
      md << "**" << f.flight << ", " << name(w.kind) << ", IG " << fixed(slowest.renderRateHz, 0) << " Hz**: field "
         << w.worst.field << ", frame " << fixed(w.worst.score.ageMs, 1) << " ms old, "
         << fixed(w.worst.score.psnrDb, 2) << " dB, " << fixed(w.worst.score.meanErrPx, 2) << " px mean error.\n\n"
         << "![" << f.flight << ' ' << name(w.kind) << "](" << file << ")\n\n";
    }
  }

  // The full table
  md << "## Every flight, IG rate and warp\n\n";
  for (const FlightResults& f : in.flights) {
    md << "### " << f.flight << " (minimum terrain clearance " << fixed(f.clearanceM, 0) << " m)\n\n"
       << "| IG Hz | poses | age ms | warp | PSNR dB | min dB | err px | p95 px | max px | viol/field | fallbacks | "
          "cost "
          "ms |\n"
       << "| ---: | --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
    for (const RateResult& r : f.rates)
      for (const WarpScore& w : r.warps)
        md << "| " << fixed(r.renderRateHz, 0) << " | " << toString(r.poses) << " | " << fixed(r.meanFrameAgeMs, 1)
           << " | " << name(w.kind) << " | " << fixed(w.meanPsnrDb, 2) << " | " << fixed(w.minPsnrDb, 2) << " | "
           << fixed(w.meanErrPx, 3) << " | " << fixed(w.p95ErrPx, 3) << " | " << fixed(w.maxErrPx, 2) << " | "
           << fixed(w.violationsPerField, 1) << " | " << w.fallbacks << " | " << fixed(w.medianCostMs, 3) << " |\n";
    md << '\n';
  }
  md << "## Files\n\n"
     << "- `warps.csv`: the table above, one row per flight, IG rate, field poses and warp.\n"
     << "- `fields.csv`: every field: frame age, PSNR and mean geometric error per warp and field poses.\n"
     << "- `needed_rate.csv`: the first table.\n"
     << "- `plots/*.dat`, `plots/gnuplot.log`: what the plots are drawn from "
        "(`tools/latency/plots.gnuplot`; the plots show the exact poses).\n";
}

}  // namespace

std::optional<double> neededRateHz(const FlightResults& flight, FieldPoses poses, warp::WarpKind kind, double limitPx) {
  std::vector<std::pair<double, double>> byRate;  // (rate, mean error)
  for (const RateResult& r : flight.rates)
    if (const WarpScore* w = scoreOf(r, kind); w != nullptr && r.poses == poses)
      byRate.emplace_back(r.renderRateHz, w->meanErrPx);
  std::sort(byRate.begin(), byRate.end());
  std::optional<double> needed;
  for (auto it = byRate.rbegin(); it != byRate.rend() && it->second < limitPx; ++it) needed = it->first;
  return needed;
}

std::optional<std::string> writeReport(const fs::path& dir, const ReportInput& input, const fs::path& plotScript) {
  fs::create_directories(dir / "plots");
  writeCsvFiles(dir, input);
  writePlotData(dir / "plots", input);
  for (const FlightResults& f : input.flights) {
    const RateResult* slowest = slowestExact(f);
    if (slowest == nullptr) continue;
    for (const WarpScore& w : slowest->warps)
      if (w.worst.field >= 0)
        writeStrip(dir / ("worst_" + oneWord(f.flight) + "_" + name(w.kind) + ".png"), w.worst,
                   input.spec.scan == ScanMode::Interlaced);
  }
  const std::optional<std::string> plotProblem = drawPlots(dir, input, plotScript);
  writeMarkdown(dir, input, plotProblem);
  return plotProblem;
}

}  // namespace fieldcast::tools
