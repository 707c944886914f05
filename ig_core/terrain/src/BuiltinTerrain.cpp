// The built-in terrain generator. The large forms (coast, plains, fold mountains, the Long Ridge,
// the island, the river valley) are analytic functions of the normalised position evaluated on a
// grid 4 voxels apart and interpolated with Catmull-Rom splines (C¹, so hillshade shows no grid);
// fine detail (a 40 m noise octave on the spline grid, 17 m and 7.3 m octaves per voxel) and the
// river channel are added per voxel.
#include <ig_core/BuiltinTerrain.h>

#include <ig_core/TerrainDatabase.h>

#include "Noise.h"
#include "Parallel.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/file.h>
#include <unistd.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace fieldcast::core {
namespace {

using detail::smoothstep;
constexpr double kTau = 2.0 * std::numbers::pi;
constexpr double kHeightBaseM = -10.0;
constexpr double kHeightStepM = 0.05;
constexpr int kCoarseStride = 4;

// Long Ridge: a crest line between two points (normalised coordinates) standing out of the foothills.
constexpr glm::dvec2 kRidgeWest{0.05, 0.35};
constexpr glm::dvec2 kRidgeEast{0.40, 0.47};
constexpr double kRidgeHalfWidth = 0.022;
constexpr double kRidgeHeightM = 620.0;
constexpr glm::dvec2 kIsland{0.30, 0.065};
constexpr double kIslandRadius = 0.028;

struct MacroSample {
  double heightM;
  double roughnessM;  // amplitude of the per-voxel detail
};

// The analytic landscape in normalised coordinates u (east) and v (north), both in [0, 1].
class Shape {
 public:
  explicit Shape(const BuiltinTerrainSpec& spec)
      : mExtentM(spec.sizeVox * spec.spacingM),
        mAmp(std::sqrt(std::min(1.0, mExtentM / 16384.0))),
        mSeed(
            detail::hashLattice(static_cast<int>(spec.seed & 0x7FFFFFFF), static_cast<int>(spec.seed >> 31), 0xF1E1D)) {
    for (int k = 0; k < 3; ++k) mPhase[k] = kTau * detail::unitFromHash(detail::hashLattice(k, 99, mSeed));
  }

  double extentM() const noexcept { return mExtentM; }
  std::uint32_t seed() const noexcept { return mSeed; }

  // Northern edge of the sea at longitude u: a wavy line with a bay in the east and a headland in the west.
  double coastV(double u) const noexcept {
    return 0.15 + 0.03 * detail::fbm(static_cast<float>(u * 5.0), 0.37f, 3, mSeed + 1) +
           0.012 * detail::fbm(static_cast<float>(u * 40.0), 0.71f, 4, mSeed + 8) +
           0.06 * std::exp(-sq((u - 0.78) / 0.06)) - 0.035 * std::exp(-sq((u - 0.20) / 0.05));
  }
  // The river's centre line: a function of v so it never doubles back; meanders more in the plains.
  double riverU(double v) const noexcept {
    return 0.56 + 0.045 * std::sin(kTau * 1.1 * v + mPhase[0]) + 0.02 * std::sin(kTau * 2.7 * v + mPhase[1]) +
           0.012 * (1.0 - smoothstep(0.35, 0.6, v)) * std::sin(kTau * 9.0 * v + mPhase[2]);
  }
  // Valley floor height along the river, rising monotonically upstream (north).
  double riverFloorM(double v) const noexcept {
    return mAmp *
           (0.6 + 30.0 * std::clamp((v - 0.15) / 0.3, 0.0, 1.0) + 480.0 * std::pow(smoothstep(0.45, 1.0, v), 1.5));
  }
  double riverHalfWidthM(double v) const noexcept { return (0.0010 + 0.0014 * (1.0 - v)) * mExtentM; }
  // Whether the river runs at latitude v (north of its mouth).
  bool riverFlows(double v) const noexcept { return v > coastV(riverU(v)) - 0.003; }

  MacroSample macro(double u, double v) const noexcept {
    const auto fu = static_cast<float>(u);
    const auto fv = static_cast<float>(v);
    const double d = v - coastV(u);
    const double m = smoothstep(0.42, 0.80, v + 0.06 * detail::fbm(fu * 4.0f, fv * 4.0f, 3, mSeed + 2));
    const double plains = 3.0 + mAmp * (45.0 * smoothstep(0.0, 0.28, d) +
                                        28.0 * (0.5 + 0.5 * detail::fbm(fu * 9.0f, fv * 9.0f, 4, mSeed + 3)));
    // Fold mountains: ridged noise stretched east-west so the ridges run across the river.
    const double mountains =
        mAmp * (120.0 + 1350.0 * std::pow(detail::ridged(fu * 4.5f, fv * 9.0f, 6, mSeed + 4), 1.3f) +
                250.0 * (0.5 + 0.5 * detail::fbm(fu * 3.0f, fv * 3.0f, 3, mSeed + 5)));
    double land = plains + (mountains - plains) * m;
    // The Long Ridge.
    const glm::dvec2 p{u, v};
    const glm::dvec2 seg = kRidgeEast - kRidgeWest;
    const double t = std::clamp(glm::dot(p - kRidgeWest, seg) / glm::dot(seg, seg), 0.0, 1.0);
    // A wobbling outline, a crest that rises and dips, and spurs and gullies down the flanks.
    const double dist =
        glm::length(p - (kRidgeWest + t * seg)) + 0.006 * detail::fbm(fu * 30.0f, fv * 30.0f, 3, mSeed + 9);
    const double taper = smoothstep(0.0, 0.12, t) * (1.0 - smoothstep(0.88, 1.0, t));
    const double profile = std::exp(-std::pow(std::fabs(dist) / kRidgeHalfWidth, 1.4));
    const double spurs = 0.7 + 0.3 * detail::ridged(fu * 28.0f, fv * 28.0f, 4, mSeed + 10);
    const double ridgeShape =
        taper * profile * spurs * (0.75 + 0.25 * detail::fbm(static_cast<float>(t * 8.0), 0.5f, 3, mSeed + 6));
    land += mAmp * kRidgeHeightM * ridgeShape;
    // Sea floor shelving away from the coast, and an island off the western headland.
    const double sea = -3.0 - 70.0 * smoothstep(0.0, 0.10, -d);
    const double landWeight = smoothstep(-0.006, 0.012, d);
    double h = sea + (land - sea) * landWeight + mAmp * 140.0 * std::exp(-sq(glm::length(p - kIsland) / kIslandRadius));
    // The river valley: flat floor, walls widening into a trough in the mountains.
    double valley = 1.0;
    const double floorM = riverFloorM(v);
    if (d > -0.01 && h > floorM) {
      const double halfWidth = 0.010 + 0.05 * m;
      valley = smoothstep(0.2 * halfWidth, halfWidth, std::fabs(u - riverU(v)));
      h = floorM + (h - floorM) * valley;
    }
    const double roughness = mAmp * (0.4 + 3.5 * m + 10.0 * ridgeShape) * (0.25 + 0.75 * valley) * landWeight;
    return {h, roughness};
  }

  // Ground or water surface before fine detail, with the river channel: for landmarks.
  double groundM(double u, double v) const noexcept {
    double h = macro(u, v).heightM;
    if (riverFlows(v) && std::fabs(u - riverU(v)) * mExtentM < riverHalfWidthM(v)) h = riverFloorM(v) - 0.4;
    return std::max(h, 0.0);
  }

 private:
  static double sq(double x) noexcept { return x * x; }
  double mExtentM;
  double mAmp;  // heights shrink on small test terrains so slopes stay plausible
  std::uint32_t mSeed;
  double mPhase[3] = {};
};

// Catmull-Rom weights for the kCoarseStride fractional positions.
struct CubicWeights {
  float w[kCoarseStride][4];
  CubicWeights() noexcept {
    for (int k = 0; k < kCoarseStride; ++k) {
      const float t = static_cast<float>(k) / kCoarseStride;
      w[k][0] = 0.5f * (-t * t * t + 2.0f * t * t - t);
      w[k][1] = 0.5f * (3.0f * t * t * t - 5.0f * t * t + 2.0f);
      w[k][2] = 0.5f * (-3.0f * t * t * t + 4.0f * t * t + t);
      w[k][3] = 0.5f * (t * t * t - t * t);
    }
  }
};

}  // namespace

std::vector<BuiltinLandmark> builtinLandmarks(const BuiltinTerrainSpec& spec) {
  const Shape shape(spec);
  const double s = shape.extentM();
  const auto at = [&](std::string name, double u, double v, std::string description) {
    return BuiltinLandmark{std::move(name), {u * s, v * s}, shape.groundM(u, v), std::move(description)};
  };
  // The river mouth: where the river's latitude meets the coast (fixed point iteration).
  double vMouth = 0.15;
  for (int k = 0; k < 30; ++k) vMouth = shape.coastV(shape.riverU(vMouth));
  const glm::dvec2 ridgeMid = 0.5 * (kRidgeWest + kRidgeEast);
  const glm::dvec2 ridgeW = kRidgeWest + 0.15 * (kRidgeEast - kRidgeWest);
  const glm::dvec2 ridgeE = kRidgeWest + 0.85 * (kRidgeEast - kRidgeWest);
  return {
      at("river_mouth", shape.riverU(vMouth), vMouth, "estuary where the river meets the sea"),
      at("river_plains_bend", shape.riverU(0.30), 0.30, "river meandering through farmland"),
      at("valley_entrance", shape.riverU(0.55), 0.55, "river valley leaving the foothills"),
      at("valley_mountains", shape.riverU(0.80), 0.80, "glacial valley floor, walls about 1 km high"),
      at("valley_head", shape.riverU(0.97), 0.97, "upper valley near the northern edge"),
      at("long_ridge_west", ridgeW.x, ridgeW.y, "west end of the Long Ridge crest (runs ENE)"),
      at("long_ridge_mid", ridgeMid.x, ridgeMid.y, "middle of the Long Ridge crest"),
      at("long_ridge_east", ridgeE.x, ridgeE.y, "east end of the Long Ridge crest"),
      at("island", kIsland.x, kIsland.y, "island off the western headland"),
      at("bay", 0.78, shape.coastV(0.78) - 0.03, "bay in the eastern coast (open water)"),
      at("coast_west", 0.10, shape.coastV(0.10), "coastline, western stretch"),
      at("coast_east", 0.92, shape.coastV(0.92), "coastline, eastern stretch"),
      at("plains", 0.28, 0.32, "rolling farmland between the coast and the ridge"),
      at("mountains", 0.30, 0.88, "fold mountains, ridges running east-west"),
  };
}

BuiltinHeights generateBuiltinHeights(const BuiltinTerrainSpec& spec, int threads, const ProgressFn& progress) {
  if (spec.sizeVox < 64 || spec.sizeVox > kMaxDatabaseSideVox || !(spec.spacingM > 0.0)) {
    throw std::invalid_argument("built-in terrain: size " + std::to_string(spec.sizeVox) + " out of range 64.." +
                                std::to_string(kMaxDatabaseSideVox) + " or spacing not positive");
  }
  const Shape shape(spec);
  const int n = spec.sizeVox;
  const double dx = spec.spacingM;
  const double extent = shape.extentM();
  BuiltinHeights out;
  out.geometry.widthVox = n;
  out.geometry.heightVox = n;
  out.geometry.spacingM = dx;
  out.geometry.originM = {0.0, 0.0};
  out.geometry.heightBaseM = kHeightBaseM;
  out.geometry.heightStepM = kHeightStepM;
  out.geometry.levels = 1;
  const auto count = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  out.heightQ.resize(count);
  out.waterDepthM.resize(count);

  // 1. The large forms on the coarse grid, padded by one sample before and two after for the splines.
  const int coarse = (n - 1) / kCoarseStride + 4;
  std::vector<float> macroH(static_cast<std::size_t>(coarse) * coarse);
  std::vector<float> macroRough(macroH.size());
  const auto totalWork = static_cast<double>(coarse + n);
  std::atomic<int> done{0};
  const auto tick = [&](int rows) {
    const int now = done.fetch_add(rows) + rows;
    if (progress) progress("terrain", now / totalWork);
  };
  detail::parallelFor(static_cast<std::size_t>(coarse), threads, 8, [&](std::size_t begin, std::size_t end) {
    for (auto cj = static_cast<int>(begin); cj < static_cast<int>(end); ++cj) {
      const double v = (cj - 1) * kCoarseStride * dx / extent;
      for (int ci = 0; ci < coarse; ++ci) {
        const double u = (ci - 1) * kCoarseStride * dx / extent;
        const MacroSample s = shape.macro(u, v);
        // The 40 m detail octave is smooth enough for the 8 m spline grid: add it here, once.
        const auto xM = static_cast<float>((ci - 1) * kCoarseStride * dx);
        const auto yM = static_cast<float>((cj - 1) * kCoarseStride * dx);
        const double octave40 = 0.55 * s.roughnessM * detail::gradientNoise(xM / 40.0f, yM / 40.0f, shape.seed() + 20);
        macroH[static_cast<std::size_t>(cj) * coarse + ci] = static_cast<float>(s.heightM + octave40);
        macroRough[static_cast<std::size_t>(cj) * coarse + ci] = static_cast<float>(s.roughnessM);
      }
    }
    tick(static_cast<int>(end - begin));
  });

  // 2. Every voxel: spline of the large forms, fine detail, the river channel, the sea surface.
  const CubicWeights cubic;
  const std::uint32_t seed = shape.seed();
  detail::parallelFor(static_cast<std::size_t>(n), threads, 32, [&](std::size_t begin, std::size_t end) {
    std::vector<float> rowH(static_cast<std::size_t>(coarse));
    std::vector<float> rowRough(static_cast<std::size_t>(coarse));
    for (auto j = static_cast<int>(begin); j < static_cast<int>(end); ++j) {
      // Vertical spline pass: this row's values at every coarse column.
      const int cj = j / kCoarseStride;  // coarse row index of sample "1" (padding offset applied below)
      const float* wy = cubic.w[j % kCoarseStride];
      for (int ci = 0; ci < coarse; ++ci) {
        float h = 0.0f, r = 0.0f;
        for (int k = 0; k < 4; ++k) {
          const std::size_t idx = static_cast<std::size_t>(cj + k) * coarse + ci;
          h += wy[k] * macroH[idx];
          r += wy[k] * macroRough[idx];
        }
        rowH[static_cast<std::size_t>(ci)] = h;
        rowRough[static_cast<std::size_t>(ci)] = r;
      }
      const double v = j * dx / extent;
      const double yM = j * dx;
      const double riverU = shape.riverU(v);
      const double floorM = shape.riverFloorM(v);
      const double halfWidthM = shape.riverHalfWidthM(v);
      const bool river = shape.riverFlows(v);
      for (int i = 0; i < n; ++i) {
        const int ci = i / kCoarseStride;
        const float* wx = cubic.w[i % kCoarseStride];
        float hM = 0.0f, roughM = 0.0f;
        for (int k = 0; k < 4; ++k) {
          hM += wx[k] * rowH[static_cast<std::size_t>(ci + k)];
          roughM += wx[k] * rowRough[static_cast<std::size_t>(ci + k)];
        }
        const double xM = i * dx;
        const auto fx = static_cast<float>(xM);
        const auto fy = static_cast<float>(yM);
        double h = hM + std::max(roughM, 0.0f) * (0.55f * detail::gradientNoise(fx / 40.0f, fy / 40.0f, seed + 20) +
                                                  0.30f * detail::gradientNoise(fx / 17.0f, fy / 17.0f, seed + 21) +
                                                  0.15f * detail::gradientNoise(fx / 7.3f, fy / 7.3f, seed + 22));
        int depth = 0;
        if (river) {
          const double dr = std::fabs(xM / extent - riverU) * extent;
          if (dr < halfWidthM) {
            h = floorM - 0.4;  // the water surface
            depth = 1 + static_cast<int>(3.0 * (1.0 - (dr / halfWidthM) * (dr / halfWidthM)));
          } else if (dr < 2.5 * halfWidthM) {
            h = std::min(h, floorM + 0.3 + 0.1 * (dr - halfWidthM));  // low banks
          }
        }
        if (h < 0.0) {  // the sea: a flat surface at 0 m, depth kept for the colour
          depth = std::clamp(static_cast<int>(std::lround(-h)), 1, 255);
          h = 0.0;
        }
        const std::size_t k = static_cast<std::size_t>(j) * n + i;
        out.heightQ[k] =
            static_cast<std::uint16_t>(std::clamp(std::lround((h - kHeightBaseM) / kHeightStepM), 0L, 65535L));
        out.waterDepthM[k] = static_cast<std::uint8_t>(depth);
      }
    }
    tick(static_cast<int>(end - begin));
  });
  return out;
}

TerrainGrid generateBuiltinTerrain(const BuiltinTerrainSpec& spec, const ProceduralColourOptions& colour,
                                   const ProgressFn& progress) {
  BuiltinHeights heights = generateBuiltinHeights(spec, colour.threads, progress);
  if (progress) progress("colour", 0.0);
  ProceduralColourOptions options = colour;
  options.seed = colour.seed ^ static_cast<std::uint32_t>(spec.seed);
  TerrainGrid grid;
  grid.colourRgba = bakeProceduralColour(heights.geometry, heights.heightQ, heights.waterDepthM, options);
  if (progress) progress("colour", 1.0);
  grid.geometry = heights.geometry;
  grid.heightQ = std::move(heights.heightQ);
  return grid;
}

std::filesystem::path defaultCacheDir() {
  if (const char* dir = std::getenv("FIELDCAST_CACHE_DIR"); dir != nullptr && *dir != '\0') return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') {
    return std::filesystem::path(xdg) / "fieldcast";
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    return std::filesystem::path(home) / ".cache" / "fieldcast";
  }
  return std::filesystem::temp_directory_path() / "fieldcast-cache";
}

std::filesystem::path builtinDatabasePath(const std::filesystem::path& cacheDir, const BuiltinTerrainSpec& spec) {
  std::ostringstream name;
  name << "builtin-g" << kBuiltinGeneratorVersion << "-" << spec.sizeVox << "-" << std::lround(spec.spacingM * 1000.0)
       << "mm-seed" << spec.seed << ".fctdb";
  return cacheDir / name.str();
}

std::filesystem::path ensureBuiltinDatabase(const std::filesystem::path& cacheDir, const BuiltinTerrainSpec& spec,
                                            const ProgressFn& progress, int threads) {
  const std::filesystem::path path = builtinDatabasePath(cacheDir, spec);
  std::error_code ec;
  std::filesystem::create_directories(cacheDir, ec);
  if (ec) throw TerrainDatabaseError(cacheDir.string() + ": cannot create the terrain cache folder: " + ec.message());
  // One builder at a time across processes; the others wait, then find the finished file.
  const std::filesystem::path lockPath = cacheDir / ".builtin.lock";
  const int lockFd = ::open(lockPath.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lockFd < 0) throw TerrainDatabaseError(lockPath.string() + ": cannot open the cache lock file");
  struct Unlock {
    int fd;
    ~Unlock() { ::close(fd); }  // closing releases the flock
  } unlock{lockFd};
  while (::flock(lockFd, LOCK_EX) != 0 && errno == EINTR) {
  }
  if (std::filesystem::exists(path)) {
    try {
      DatabaseReader check(path);
      return path;
    } catch (const TerrainDatabaseError& e) {
      spdlog::warn("rebuilding the built-in terrain: {}", e.what());
    }
  }
  std::ostringstream job;
  job << "built-in terrain " << spec.sizeVox << "x" << spec.sizeVox << " at " << spec.spacingM << " m";
  std::unique_ptr<ConsoleProgress> console;
  ProgressFn report = progress;
  if (!report) {
    console = std::make_unique<ConsoleProgress>(job.str());
    report = console->callback();
  }
  ProceduralColourOptions colour;
  colour.threads = threads;
  const TerrainGrid grid = generateBuiltinTerrain(spec, colour, report);
  BuildOptions options;
  options.threads = threads;
  options.progress = report;
  writeTerrainDatabase(grid, path, options);
  // Databases of older generator versions will never be asked for again: free their disk space.
  // (A process still reading one keeps it open; unlinking does not disturb it.)
  const std::string current = "builtin-g" + std::to_string(kBuiltinGeneratorVersion) + "-";
  for (const auto& entry : std::filesystem::directory_iterator(cacheDir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("builtin-g", 0) == 0 && name.rfind(current, 0) != 0 && entry.path().extension() == ".fctdb") {
      spdlog::info("removing {} (an older built-in terrain generator)", entry.path().string());
      std::filesystem::remove(entry.path(), ec);
    }
  }
  return path;
}

}  // namespace fieldcast::core
