// Procedural terrain colour: a palette chosen by elevation, slope and water depth, broken up by
// noise (field patchwork on the plains, ragged forest and snow lines), fine per-voxel brightness
// noise, and Lambert hillshade from a configurable sun.
#include <ig_core/TerrainColour.h>

#include "Noise.h"
#include "Parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace fieldcast::core {
namespace {

struct Rgb {
  float r, g, b;
};

Rgb mix(const Rgb& a, const Rgb& b, double t) noexcept {
  const auto f = static_cast<float>(std::clamp(t, 0.0, 1.0));
  return {a.r + (b.r - a.r) * f, a.g + (b.g - a.g) * f, a.b + (b.b - a.b) * f};
}

constexpr Rgb kSand{196, 182, 132};
constexpr Rgb kForest{46, 72, 36};
constexpr Rgb kMeadow{112, 122, 70};
constexpr Rgb kRock{118, 108, 98};
constexpr Rgb kSnow{238, 240, 246};
constexpr Rgb kShallow{72, 138, 146};
constexpr Rgb kDeep{18, 46, 86};
// Field patchwork of the lowlands: crops, pasture, stubble, ploughed soil.
constexpr std::array<Rgb, 6> kFields = {Rgb{104, 138, 58}, Rgb{142, 152, 78}, Rgb{88, 118, 48},
                                        Rgb{168, 150, 96}, Rgb{120, 100, 72}, Rgb{96, 128, 64}};

// A smooth noise field sampled every kStride voxels and interpolated bilinearly: the large-scale
// variations (hundreds of metres) cost one evaluation per kStride² voxels instead of one each.
class CoarseField {
 public:
  static constexpr int kStride = 8;
  template <typename Fn>
  CoarseField(int w, int h, double spacingM, int threads, Fn&& noiseAtMetres)
      : mW(w / kStride + 2), mH(h / kStride + 2), mValues(static_cast<std::size_t>(mW) * mH) {
    detail::parallelFor(static_cast<std::size_t>(mH), threads, 8, [&](std::size_t begin, std::size_t end) {
      for (auto cj = static_cast<int>(begin); cj < static_cast<int>(end); ++cj) {
        for (int ci = 0; ci < mW; ++ci) {
          mValues[static_cast<std::size_t>(cj) * mW + ci] =
              noiseAtMetres(static_cast<float>(ci * kStride * spacingM), static_cast<float>(cj * kStride * spacingM));
        }
      }
    });
  }
  float at(int i, int j) const noexcept {
    const int ci = i / kStride, cj = j / kStride;
    const float tx = static_cast<float>(i % kStride) / kStride;
    const float ty = static_cast<float>(j % kStride) / kStride;
    const float* r0 = mValues.data() + static_cast<std::size_t>(cj) * mW + ci;
    const float* r1 = r0 + mW;
    return (r0[0] * (1 - tx) + r0[1] * tx) * (1 - ty) + (r1[0] * (1 - tx) + r1[1] * tx) * ty;
  }

 private:
  int mW, mH;
  std::vector<float> mValues;
};

// atan in degrees for x ≥ 0, within 0.3°: the palette needs slope classes, not exact angles.
double slopeDegrees(double tangent) noexcept {
  constexpr double kDeg = 180.0 / std::numbers::pi;
  if (tangent <= 1.0) return kDeg * tangent / (1.0 + 0.28 * tangent * tangent);
  return kDeg * (std::numbers::pi / 2 - tangent / (tangent * tangent + 0.28));
}

}  // namespace

std::vector<std::uint32_t> bakeProceduralColour(const TerrainGeometry& geometry, std::span<const std::uint16_t> heightQ,
                                                std::span<const std::uint8_t> waterDepthM,
                                                const ProceduralColourOptions& options, std::vector<LandCover>* cover) {
  const int w = geometry.widthVox;
  const int h = geometry.heightVox;
  const auto count = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (heightQ.size() != count || (!waterDepthM.empty() && waterDepthM.size() != count)) {
    throw std::invalid_argument("bakeProceduralColour: expected " + std::to_string(count) + " voxels, got " +
                                std::to_string(heightQ.size()) + " heights and " + std::to_string(waterDepthM.size()) +
                                " water depths");
  }
  const double az = options.sunAzimuthDeg * std::numbers::pi / 180.0;
  const double el = std::clamp(options.sunElevationDeg, 1.0, 90.0) * std::numbers::pi / 180.0;
  const double sunX = std::sin(az) * std::cos(el);  // towards the sun: x east, y north, z up
  const double sunY = std::cos(az) * std::cos(el);
  const double sunZ = std::sin(el);
  const double step = geometry.heightStepM;
  const double spacing = geometry.spacingM;
  const std::uint32_t seed = options.seed * 0x9E3779B9u + 0x1234567u;
  std::vector<std::uint32_t> colours(count);
  if (cover != nullptr) cover->assign(count, LandCover::Open);
  const CoarseField patchField(w, h, spacing, options.threads,
                               [seed](float x, float y) { return detail::fbm(x / 400.0f, y / 400.0f, 3, seed + 7); });
  const CoarseField jitterX(w, h, spacing, options.threads, [seed](float x, float y) {
    return detail::gradientNoise(x / 300.0f, y / 300.0f, seed + 11);
  });
  const CoarseField jitterY(w, h, spacing, options.threads, [seed](float x, float y) {
    return detail::gradientNoise(x / 300.0f, y / 300.0f, seed + 12);
  });

  detail::parallelFor(static_cast<std::size_t>(h), options.threads, 16, [&](std::size_t rowBegin, std::size_t rowEnd) {
    for (auto j = static_cast<int>(rowBegin); j < static_cast<int>(rowEnd); ++j) {
      const std::uint16_t* row = heightQ.data() + static_cast<std::size_t>(j) * w;
      const std::uint16_t* north = heightQ.data() + static_cast<std::size_t>(std::min(j + 1, h - 1)) * w;
      const std::uint16_t* south = heightQ.data() + static_cast<std::size_t>(std::max(j - 1, 0)) * w;
      for (int i = 0; i < w; ++i) {
        const std::size_t k = static_cast<std::size_t>(j) * w + i;
        const double zM = geometry.heightM(row[i]);
        const float xM = static_cast<float>(i * spacing);
        const float yM = static_cast<float>(j * spacing);
        // Slope and normal from central differences.
        const double dzdx =
            (static_cast<double>(row[std::min(i + 1, w - 1)]) - row[std::max(i - 1, 0)]) * step / (2.0 * spacing);
        const double dzdy = (static_cast<double>(north[i]) - south[i]) * step / (2.0 * spacing);
        const double gradient = std::sqrt(dzdx * dzdx + dzdy * dzdy);
        const double slopeDeg = slopeDegrees(gradient);
        const float patch = patchField.at(i, j);  // large-scale variation
        const int depth = waterDepthM.empty()
                              ? (zM <= options.seaLevelM ? 1 + static_cast<int>(options.seaLevelM - zM) : 0)
                              : waterDepthM[k];
        Rgb c{};
        bool water = depth > 0;
        if (water) {
          c = mix(kShallow, kDeep, std::sqrt(std::min(depth, 40) / 40.0));
          if (cover != nullptr) (*cover)[k] = LandCover::Water;
        } else {
          // Lowland fields: a patchwork of rectangles about 60–120 m, jittered.
          const auto fieldX = [&](int ii, int jj) {
            return static_cast<int>(std::floor(static_cast<float>(ii * spacing) / 90.0f + 0.3f * jitterX.at(ii, jj)));
          };
          const auto fieldY = [&](int ii, int jj) {
            return static_cast<int>(std::floor(static_cast<float>(jj * spacing) / 70.0f + 0.3f * jitterY.at(ii, jj)));
          };
          const int cellX = fieldX(i, j), cellY = fieldY(i, j);
          const std::uint32_t cell = detail::hashLattice(cellX, cellY, seed + 13);
          Rgb land = kFields[cell % kFields.size()];
          // Forest on slopes and at mid elevation, with a ragged edge from noise.
          const double forestEdge = 0.5 + 0.5 * patch;
          const double forest =
              detail::smoothstep(0.55, 0.75,
                                 forestEdge + 0.015 * slopeDeg + 0.35 * detail::smoothstep(60.0, 400.0, zM) -
                                     detail::smoothstep(1100.0, 1400.0, zM));
          land = mix(land, kForest, forest);
          land = mix(land, kMeadow, detail::smoothstep(1150.0, 1400.0, zM + 120.0 * patch) * (1.0 - forest * 0.5));
          // Beaches: low and flat near the sea.
          land = mix(land, kSand,
                     (1.0 - detail::smoothstep(1.5, 4.0, zM - options.seaLevelM)) *
                         (1.0 - detail::smoothstep(6.0, 14.0, slopeDeg)));
          // Bare rock on steep slopes and high up; snow high and not too steep.
          land = mix(land, kRock,
                     std::max(detail::smoothstep(32.0, 45.0, slopeDeg + 6.0 * patch),
                              detail::smoothstep(1450.0, 1650.0, zM + 100.0 * patch)));
          const double snow =
              detail::smoothstep(1650.0, 1800.0, zM + 150.0 * patch) * (1.0 - detail::smoothstep(40.0, 55.0, slopeDeg));
          land = mix(land, kSnow, snow);
          c = land;
          if (cover != nullptr) {
            const double rock = std::max(detail::smoothstep(32.0, 45.0, slopeDeg + 6.0 * patch),
                                         detail::smoothstep(1450.0, 1650.0, zM + 100.0 * patch));
            const double sand = (1.0 - detail::smoothstep(1.5, 4.0, zM - options.seaLevelM));
            LandCover& here = (*cover)[k];
            if (forest > 0.6 && rock < 0.3 && snow < 0.3) {
              here = LandCover::Forest;
            } else if (forest < 0.2 && rock < 0.2 && sand < 0.2 && zM < 1100.0) {
              const bool edge = (i > 0 && fieldX(i - 1, j) != cellX) || (j > 0 && fieldY(i, j - 1) != cellY);
              here = edge ? LandCover::FieldEdge : LandCover::Field;
            }
          }
        }
        // Lambert hillshade normalised so flat ground keeps its palette brightness.
        double light = 1.0;
        if (!water) {
          const double nLen = std::sqrt(dzdx * dzdx + dzdy * dzdy + 1.0);
          const double lambert = std::max(0.0, (-dzdx * sunX - dzdy * sunY + sunZ) / nLen);
          light = (1.0 - options.hillshade) + options.hillshade * lambert / sunZ;
        }
        // Fine noise: per voxel plus an 8 m octave, so close-up ground is not flat paint.
        const double grain = 2.0 * detail::unitFromHash(detail::hashLattice(i, j, seed)) - 1.0;
        const double fine = detail::gradientNoise(xM / 8.0f, yM / 8.0f, seed + 3);
        light *= 1.0 + options.noise * (water ? 0.2 : 1.0) * (0.5 * grain + 0.7 * fine);
        light = std::clamp(light, 0.15, 1.6);
        const auto channel = [light](float v) {
          return static_cast<std::uint32_t>(std::clamp(std::lround(v * light), 0L, 255L));
        };
        std::uint32_t r = channel(c.r), g = channel(c.g), b = channel(c.b);
        if (options.output == ColourOutput::Grey) r = g = b = (77u * r + 150u * g + 29u * b + 128u) >> 8;
        colours[k] = packRgba(r, g, b);
      }
    }
  });
  return colours;
}

}  // namespace fieldcast::core
