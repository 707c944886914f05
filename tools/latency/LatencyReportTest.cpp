// fieldcast-latency as a user runs it: `--quick` writes the whole report folder, every table row
// is finite, the plots are real PNG files, and the report says what it measured: the quadratic
// beats hold on the turn, and both inputs reach the emitted fields. Plus the "needed rate" finding, on hand-made
// figures.
#include "../../tests/common/MachineStallWatch.h"
#include "EmittedFields.h"
#include "Report.h"

#include <ig_core/BuiltinTerrain.h>

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace fieldcast::tools {
namespace {

namespace fs = std::filesystem;

FlightResults flightWithErrors(const std::vector<std::pair<double, double>>& rateAndError) {
  FlightResults f;
  f.flight = "made up";
  for (const auto& [rate, error] : rateAndError) {
    RateResult r;
    r.renderRateHz = rate;
    WarpScore w;
    w.kind = warp::WarpKind::Quadratic;
    w.meanErrPx = error;
    r.warps.push_back(w);
    f.rates.push_back(r);
  }
  return f;
}

TEST(NeededRate, IsTheSlowestRateFromWhichEveryFasterOneStaysUnderTheLimit) {
  constexpr auto kExact = FieldPoses::Exact;
  constexpr auto kQuadratic = warp::WarpKind::Quadratic;
  EXPECT_EQ(neededRateHz(flightWithErrors({{5, 2.0}, {10, 0.9}, {30, 0.3}}), kExact, kQuadratic, 1.0), 10.0);
  EXPECT_EQ(neededRateHz(flightWithErrors({{5, 0.5}, {10, 0.4}}), kExact, kQuadratic, 1.0), 5.0);
  // A rate that dips under the limit below one that does not is not enough
  EXPECT_EQ(neededRateHz(flightWithErrors({{5, 0.9}, {10, 1.2}, {30, 0.3}}), kExact, kQuadratic, 1.0), 30.0);
  EXPECT_FALSE(neededRateHz(flightWithErrors({{5, 3.0}, {60, 1.5}}), kExact, kQuadratic, 1.0).has_value());
  // Not evaluated: a warp, or field poses, the run did not have
  EXPECT_FALSE(neededRateHz(flightWithErrors({{5, 0.1}}), kExact, warp::WarpKind::Hold, 1.0).has_value());
  EXPECT_FALSE(neededRateHz(flightWithErrors({{5, 0.1}}), FieldPoses::HostPredicted, kQuadratic, 1.0).has_value());
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
  return cells;
}

std::string readFile(const fs::path& path) {
  std::ifstream in(path);
  std::string text, line;
  while (std::getline(in, line)) text += line + '\n';
  return text;
}

bool isPng(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in && std::string(magic, 8) == std::string("\x89PNG\r\n\x1a\n", 8) && fs::file_size(path) > 1000;
}

TEST(RollSignal, IsTheLeftSidesDownwardShiftMinusTheRightSides) {
  // Rows of random grey, 64 wide × 120 rows; the second picture has its left quarter moved down by
  // 3 rows and its right quarter up by 3 (a roll to the left), the middle untouched
  constexpr int kW = 64, kRows = 120;
  std::mt19937 rng(5);
  std::vector<int> rowValue(kRows + 20);
  for (int& v : rowValue) v = static_cast<int>(rng() % 200) + 20;
  std::string a(kW * kRows, '\0'), b = a;
  for (int y = 0; y < kRows; ++y)
    for (int x = 0; x < kW; ++x) {
      a[static_cast<std::size_t>(y * kW + x)] = static_cast<char>(rowValue[static_cast<std::size_t>(y + 10)]);
      const int shift = x < kW / 4 ? 3 : (x >= kW - kW / 4 ? -3 : 0);
      b[static_cast<std::size_t>(y * kW + x)] = static_cast<char>(rowValue[static_cast<std::size_t>(y + 10 - shift)]);
    }
  EXPECT_NEAR(verticalShiftRows(a, b, kW, 0, kW / 4), 3.0, 0.05);
  EXPECT_NEAR(rollSignalRows(a, b, kW), 6.0, 0.1);
  EXPECT_NEAR(rollSignalRows(a, a, kW), 0.0, 1e-9);
}

TEST(LatencyReport, QuickRunWritesAFiniteReportWhereTheQuadraticBeatsHoldOnTheTurn) {
  const fs::path dir = fs::temp_directory_path() / ("fieldcast_latency_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string command = std::string(FIELDCAST_LATENCY_BIN) + " --quick --threads 2 --fieldcast " + FIELDCAST_EXE +
                              " --out " + dir.string() + " > " + (dir.string() + ".log") + " 2>&1";
  fieldcast::testing::MachineStallWatch stalls;  // the machine's own stalls, beside the run
  const int status = std::system(command.c_str());
  const bool machineStalled = stalls.fieldsDueInStalls() > 0;
  const std::string log = readFile(dir.string() + ".log");
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << log;

  for (const char* file : {"report.md", "warps.csv", "fields.csv", "needed_rate.csv", "plots/rates.dat"})
    EXPECT_TRUE(fs::is_regular_file(dir / file)) << file;
  for (const char* png : {"psnr_vs_rate.png", "error_vs_age.png", "cost_vs_fidelity.png", "e2e_latency.png",
                          "worst_eval_turn30_quadratic.png", "worst_eval_lowpass250_mesh.png"})
    EXPECT_TRUE(isPng(dir / png)) << png;

  // Every row of the table: four flights × two rates × two kinds of field pose × six warps,
  // every figure finite
  std::ifstream csv(dir / "warps.csv");
  std::string line;
  std::getline(csv, line);
  const std::vector<std::string> header = splitCsv(line);
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t flightCol = column("flight"), rateCol = column("render_hz"), posesCol = column("poses"),
                    warpCol = column("warp"), psnrCol = column("psnr_db"), errCol = column("err_px");
  int rows = 0;
  // (poses, rate) → warp → figure, on the turn
  std::map<std::string, std::map<std::string, double>> turnPsnr, turnError;
  while (std::getline(csv, line)) {
    const std::vector<std::string> cells = splitCsv(line);
    ASSERT_EQ(cells.size(), header.size()) << line;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (i == flightCol || i == posesCol || i == warpCol) continue;  // names
      EXPECT_TRUE(std::isfinite(std::stod(cells[i]))) << header[i] << " in " << line;
    }
    if (cells[flightCol] == "eval_turn30") {
      const std::string key = cells[posesCol] + " " + cells[rateCol];
      turnPsnr[key][cells[warpCol]] = std::stod(cells[psnrCol]);
      turnError[key][cells[warpCol]] = std::stod(cells[errCol]);
    }
    ++rows;
  }
  EXPECT_EQ(rows, 4 * 2 * 2 * 6);
  ASSERT_EQ(turnPsnr.size(), 4u);
  for (const auto& [key, psnr] : turnPsnr) {
    // In the banked turn a held frame lacks the whole bank; the quadratic follows it, with the
    // exact pose and with the pose predicted from the host's samples
    EXPECT_GT(psnr.at("quadratic"), psnr.at("hold") + 10.0) << key;
    EXPECT_LT(turnError[key].at("quadratic"), 0.1 * turnError[key].at("hold")) << key;
  }

  // The report names its command and carries its finding and its plots
  const std::string md = readFile(dir / "report.md");
  EXPECT_NE(md.find("fieldcast-latency --quick"), std::string::npos);
  EXPECT_NE(md.find("## The IG rate each warp needs"), std::string::npos);
  EXPECT_NE(md.find("| eval_lowpass250 |"), std::string::npos);
  EXPECT_NE(md.find("![PSNR against IG rate"), std::string::npos);
  EXPECT_NE(md.find("## Pose prediction from a host"), std::string::npos);
  // The running service's stick → field and host → field latency: every step found in the poses,
  // most in the pixels. (A step is thrown for 150 ms and looked for over 300 ms: when the machine
  // itself stalled during the run, one may have gone unseen.)
  const auto foundInPoses = [&](const std::string& path) {
    return md.find("| " + path + " | pose | 8 of 8 |") != std::string::npos ||
           (machineStalled && md.find("| " + path + " | pose | 7 of 8 |") != std::string::npos);
  };
  EXPECT_TRUE(foundInPoses("stick")) << md;
  EXPECT_NE(md.find("| stick | pixels | "), std::string::npos);
  EXPECT_TRUE(foundInPoses("host")) << md;
  EXPECT_NE(md.find("| host | pixels | "), std::string::npos);
  EXPECT_EQ(md.find("could not be drawn"), std::string::npos);
  if (!HasFailure()) {
    fs::remove_all(dir);
    fs::remove(dir.string() + ".log");
  }
}

TEST(LatencyReport, EvaluatesADatabaseGivenWithDbAndRefusesFlightsOffIt) {
  const fs::path dir = fs::temp_directory_path() / ("fieldcast_latency_db_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const fs::path database = core::ensureBuiltinDatabase(dir, {1024, 2.0, 1}, [](std::string_view, double) {});
  // Eastward at 80 m/s, 150 m over the 2 km square's south half, looking 15° down
  std::ofstream(dir / "east.toml") << "name = \"east\"\ncamera_pitch_deg = -15\n"
                                   << "[[waypoint]]\nt = 0\nposition = [300, 500, 350]\n"
                                   << "[[waypoint]]\nt = 5\nposition = [700, 500, 350]\n";
  const std::string tool = std::string(FIELDCAST_LATENCY_BIN) + " --db " + database.string() +
                           " --no-e2e --exact-only --threads 2 --width 160 --height 120 --fields 20 --rates 10";
  const std::string log = dir.string() + "/run.log";
  const int status = std::system((tool + " --flight " + (dir / "east.toml").string() + " --out " +
                                  (dir / "report").string() + " > " + log + " 2>&1")
                                     .c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << readFile(log);
  const std::string md = readFile(dir / "report/report.md");
  EXPECT_NE(md.find("Database " + database.filename().string() + ", 1024 × 1024 voxels at 2.00 m, every tile resident"),
            std::string::npos)
      << md;
  // The terrain was there: over it the quadratic follows the forward flight that hold lags
  std::ifstream csv(dir / "report/warps.csv");
  std::string line;
  std::getline(csv, line);
  const std::vector<std::string> header = splitCsv(line);
  const auto psnrCol = static_cast<std::size_t>(std::find(header.begin(), header.end(), "psnr_db") - header.begin());
  const auto warpCol = static_cast<std::size_t>(std::find(header.begin(), header.end(), "warp") - header.begin());
  std::map<std::string, double> psnr;
  while (std::getline(csv, line)) {
    const std::vector<std::string> cells = splitCsv(line);
    ASSERT_GT(cells.size(), std::max(psnrCol, warpCol)) << line;
    psnr[cells[warpCol]] = std::stod(cells[psnrCol]);
  }
  ASSERT_EQ(psnr.size(), 6u);
  EXPECT_GT(psnr.at("quadratic"), psnr.at("hold") + 3.0);

  // A flight that crosses the east edge (x 2047 m) at 0.47 s (first sampled beyond it at 0.48 s) is refused, naming
  // where
  std::ofstream(dir / "off.toml") << "name = \"off\"\n[[waypoint]]\nt = 0\nposition = [2000, 500, 350]\n"
                                  << "[[waypoint]]\nt = 5\nposition = [2500, 500, 350]\n";
  const int refused = std::system((tool + " --flight " + (dir / "off.toml").string() + " --out " +
                                   (dir / "refused").string() + " > " + log + " 2>&1")
                                      .c_str());
  EXPECT_TRUE(WIFEXITED(refused) && WEXITSTATUS(refused) != 0);
  EXPECT_NE(readFile(log).find("flight 'off' is at (2048.0, 500.0) at 0.48 s, outside the terrain's x -1.0 … 2047.0"),
            std::string::npos)
      << readFile(log);
  if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace fieldcast::tools
