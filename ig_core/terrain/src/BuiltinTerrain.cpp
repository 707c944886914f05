// The built-in terrain generator. The large forms (coast, plains, fold mountains, the Long Ridge,
// the island, the river valley) are analytic functions of the normalised position evaluated on a
// grid 4 voxels apart and interpolated with Catmull-Rom splines (C¹, so hillshade shows no grid);
// fine detail (a 40 m noise octave on the spline grid, 17 m and 7.3 m octaves per voxel) and the
// river channel are added per voxel.
#include <ig_core/BuiltinTerrain.h>

#include <ig_core/ObjectPlacement.h>
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
#include <utility>

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

// ---- Objects ----------------------------------------------------------------------------------------

// Where the built-in terrain's objects go, from its shape and what its colour painted each voxel:
// villages (houses, barns and a church) on the river's banks every 1.5 km through the lowlands,
// farmsteads (a house, a barn, trees) among the fields about every 350 m, woods on its forests (a
// tree every 6 m, conifers up high, broadleaves below), hedgerows along its fields' edges (with
// gaps). Deterministic for the seed.
class Furnisher {
 public:
  Furnisher(const Shape& shape, TerrainGrid& grid, const std::vector<LandCover>& cover, int threads)
      : mShape(shape), mGrid(grid), mCover(cover), mPlacer(grid), mSeed(shape.seed() ^ 0x0B1EC75u), mThreads(threads) {}

  PlacementReport run(const ProgressFn& progress) {
    placeVillages();
    placeFarmsteads();
    if (progress) progress("objects", 0.2);
    placeWoods();
    if (progress) progress("objects", 0.7);
    placeHedgerows();
    flush();
    if (progress) progress("objects", 1.0);
    return mPlacer.finish();
  }

 private:
  static constexpr double kVillageRadiusM = 110.0;

  double unit(int a, int b, std::uint32_t salt) const noexcept {
    return detail::unitFromHash(detail::hashLattice(a, b, mSeed + salt));
  }
  int side() const noexcept { return mGrid.geometry.widthVox; }
  double spacing() const noexcept { return mGrid.geometry.spacingM; }
  // The voxel under world (x, y), or -1 off the grid
  long voxelAt(double xM, double yM) const noexcept {
    const long i = std::lround(xM / spacing()), j = std::lround(yM / spacing());
    return i < 0 || j < 0 || i >= side() || j >= side() ? -1 : j * side() + i;
  }
  bool dryLand(double xM, double yM) const noexcept {
    const long k = voxelAt(xM, yM);
    return k >= 0 && mCover[static_cast<std::size_t>(k)] != LandCover::Water;
  }
  bool inVillage(double xM, double yM) const noexcept {
    return std::any_of(mVillages.begin(), mVillages.end(), [&](const glm::dvec2& c) {
      return glm::length(glm::dvec2{xM, yM} - c) < kVillageRadiusM;
    });
  }

  // Objects are chosen here one after another and placed in that order, in batches whose
  // footprints are found on every core. No choice reads what was placed before it.
  static constexpr std::size_t kQueuedObjects = 65536;  // chosen objects held before they are placed
  void queue(const VoxelModel& model, double xM, double yM, double headingDeg, double scale) {
    mRequests.push_back({&model, xM, yM, headingDeg, scale});
    if (mRequests.size() >= kQueuedObjects) flush();
  }
  void flush() {
    mPlacer.place(mRequests, mThreads);
    mRequests.clear();
  }

  void placeVillages() {
    const double extent = mShape.extentM();
    const VoxelModel& house = *findBuiltinModel("house");
    const VoxelModel& barn = *findBuiltinModel("barn");
    const VoxelModel& church = *findBuiltinModel("church");
    int k = 0;
    for (double yM = 0.18 * extent; yM < 0.50 * extent; yM += 1500.0, ++k) {
      const double v = yM / extent;
      if (!mShape.riverFlows(v) || v < mShape.coastV(mShape.riverU(v)) + 0.02) continue;
      // On the bank, alternately east and west, along the river's course
      const double bankM = mShape.riverHalfWidthM(v) + 40.0 + kVillageRadiusM;
      const double side = k % 2 == 0 ? 1.0 : -1.0;
      const glm::dvec2 centre{mShape.riverU(v) * extent + side * bankM, yM};
      if (!dryLand(centre.x, centre.y)) continue;
      const double dv = 0.002;
      const double along = std::atan2((mShape.riverU(v + dv) - mShape.riverU(v - dv)) * extent, 2.0 * dv * extent);
      const double streetDeg = along * 180.0 / std::numbers::pi;  // the river's heading
      mVillages.push_back(centre);
      queue(church, centre.x, centre.y, streetDeg, 1.0);
      // Houses on a jittered grid of 22 m around the church, barns at the edge
      for (int gy = -4; gy <= 4; ++gy) {
        for (int gx = -4; gx <= 4; ++gx) {
          if (std::abs(gx) <= 1 && std::abs(gy) <= 1) continue;  // the church's square
          const double r = std::hypot(gx, gy) * 22.0;
          if (r > kVillageRadiusM - 10.0 || unit(gx + 16 * k, gy, 1) < 0.35) continue;
          const double a = along;
          const double ox = gx * 22.0 + 5.0 * (unit(gx, gy + 16 * k, 2) - 0.5);
          const double oy = gy * 22.0 + 5.0 * (unit(gx, gy + 16 * k, 3) - 0.5);
          const double x = centre.x + ox * std::cos(a) + oy * std::sin(a);
          const double y = centre.y - ox * std::sin(a) + oy * std::cos(a);
          if (!dryLand(x, y)) continue;
          const bool isBarn = r > 70.0 && unit(gx, gy, 4 + k) < 0.4;
          const double heading =
              streetDeg + 90.0 * std::floor(4.0 * unit(gx, gy, 5 + k)) + 8.0 * (unit(gx, gy, 6) - 0.5);
          queue(isBarn ? barn : house, x, y, heading, 0.9 + 0.25 * unit(gx, gy, 7 + k));
        }
      }
    }
  }

  void placeFarmsteads() {
    const VoxelModel& house = *findBuiltinModel("house");
    const VoxelModel& barn = *findBuiltinModel("barn");
    const VoxelModel& broadleaf = *findBuiltinModel("broadleaf");
    constexpr double kEveryM = 350.0;
    const int cells = static_cast<int>(side() * spacing() / kEveryM);
    const auto inField = [&](double x, double y) {
      const long k = voxelAt(x, y);
      return k >= 0 && (mCover[static_cast<std::size_t>(k)] == LandCover::Field ||
                        mCover[static_cast<std::size_t>(k)] == LandCover::FieldEdge);
    };
    for (int cj = 0; cj < cells; ++cj) {
      for (int ci = 0; ci < cells; ++ci) {
        const double x = (ci + 0.2 + 0.6 * unit(ci, cj, 31)) * kEveryM;
        const double y = (cj + 0.2 + 0.6 * unit(ci, cj, 32)) * kEveryM;
        // Among fields all round (not on a slope into woods, rock or water), away from villages
        bool fields = true;
        for (const auto& [ox, oy] : {std::pair{-30.0, -30.0}, {30.0, -30.0}, {-30.0, 30.0}, {30.0, 30.0}, {0.0, 0.0}})
          fields = fields && inField(x + ox, y + oy);
        if (!fields || inVillage(x, y) || unit(ci, cj, 33) < 0.2) continue;
        const double heading = 90.0 * std::floor(4.0 * unit(ci, cj, 34)) + 10.0 * (unit(ci, cj, 35) - 0.5);
        const double a = heading * std::numbers::pi / 180.0;
        // The barn 22 m east of the house (in the farm's own frame), two trees to the west
        const auto at = [&](double ox, double oy) {
          return glm::dvec2{x + ox * std::cos(a) + oy * std::sin(a), y - ox * std::sin(a) + oy * std::cos(a)};
        };
        queue(house, x, y, heading, 1.0);
        const glm::dvec2 b = at(22.0, 4.0), t1 = at(-14.0, 8.0), t2 = at(-12.0, -9.0);
        queue(barn, b.x, b.y, heading + 90.0, 1.0);
        queue(broadleaf, t1.x, t1.y, 0.0, 1.1);
        queue(broadleaf, t2.x, t2.y, 0.0, 0.9);
      }
    }
  }

  void placeWoods() {
    const VoxelModel& conifer = *findBuiltinModel("conifer");
    const VoxelModel& broadleaf = *findBuiltinModel("broadleaf");
    constexpr int kEvery = 3;  // voxels between trees (6 m at 2 m)
    for (int cj = 0; cj < side() / kEvery; ++cj) {
      for (int ci = 0; ci < side() / kEvery; ++ci) {
        const int i = ci * kEvery + static_cast<int>(kEvery * unit(ci, cj, 11));
        const int j = cj * kEvery + static_cast<int>(kEvery * unit(ci, cj, 12));
        const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(side()) + i;
        if (mCover[k] != LandCover::Forest || unit(ci, cj, 13) > 0.85) continue;
        const double x = i * spacing(), y = j * spacing();
        if (inVillage(x, y)) continue;
        const double groundM = mGrid.geometry.heightM(mPlacer.groundQ(k));
        const bool needles = groundM > 350.0 || unit(ci, cj, 14) < 0.3;
        queue(needles ? conifer : broadleaf, x, y, 360.0 * unit(ci, cj, 15), 0.75 + 0.5 * unit(ci, cj, 16));
      }
    }
  }

  void placeHedgerows() {
    const VoxelModel& hedge = *findBuiltinModel("hedge");
    for (int j = 0; j < side(); ++j) {
      for (int i = 0; i < side(); ++i) {
        const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(side()) + i;
        if (mCover[k] != LandCover::FieldEdge || unit(i / 8, j / 8, 21) < 0.25) continue;  // gaps of 16 m
        const double x = i * spacing(), y = j * spacing();
        if (inVillage(x, y)) continue;
        queue(hedge, x, y, 0.0, 0.8 + 0.4 * unit(i, j, 22));
      }
    }
  }

  const Shape& mShape;
  TerrainGrid& mGrid;
  const std::vector<LandCover>& mCover;
  ObjectPlacer mPlacer;
  std::uint32_t mSeed;
  int mThreads;
  std::vector<PlacementRequest> mRequests;  // chosen, not yet placed
  std::vector<glm::dvec2> mVillages;
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
  std::vector<LandCover> cover;
  grid.colourRgba = bakeProceduralColour(heights.geometry, heights.heightQ, heights.waterDepthM, options, &cover);
  if (progress) progress("colour", 1.0);
  grid.geometry = heights.geometry;
  grid.heightQ = std::move(heights.heightQ);
  if (spec.objects) {
    const Shape shape(spec);
    const PlacementReport placed = Furnisher(shape, grid, cover, colour.threads).run(progress);
    spdlog::debug("built-in terrain: {} objects, {} voxels with sticks, {} stick table entries", placed.placed,
                  placed.stickVoxels, placed.tableEntries);
  }
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
       << "mm-seed" << spec.seed << (spec.objects ? "" : "-bare") << ".fctdb";
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
