// Procedural test terrains: value noise summed over octaves for the hills, an elevation palette
// modulated by per-voxel texture for the colour. Simple on purpose: it only has to be a height
// field with detail at every scale, which is what stresses the ray caster.
#include <ig_core/SyntheticTerrain.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace fieldcast::core {
namespace {

std::uint32_t hash2(int x, int y, std::uint32_t seed) noexcept {
  std::uint32_t h =
      static_cast<std::uint32_t>(x) * 0x8da6b343u ^ static_cast<std::uint32_t>(y) * 0xd8163841u ^ seed * 0xcb1ab31fu;
  h ^= h >> 13;
  h *= 0x85ebca6bu;
  h ^= h >> 16;
  return h;
}

double unitNoise(int x, int y, std::uint32_t seed) noexcept { return (hash2(x, y, seed) & 0xFFFFFFu) / 16777215.0; }

// Smoothly interpolated value noise in [0, 1] with lattice period `cell` voxels.
double valueNoise(double x, double y, double cell, std::uint32_t seed) noexcept {
  const double fx = x / cell;
  const double fy = y / cell;
  const int ix = static_cast<int>(std::floor(fx));
  const int iy = static_cast<int>(std::floor(fy));
  const double tx = fx - ix;
  const double ty = fy - iy;
  const double sx = tx * tx * (3.0 - 2.0 * tx);
  const double sy = ty * ty * (3.0 - 2.0 * ty);
  const double a = unitNoise(ix, iy, seed);
  const double b = unitNoise(ix + 1, iy, seed);
  const double c = unitNoise(ix, iy + 1, seed);
  const double d = unitNoise(ix + 1, iy + 1, seed);
  return (a * (1 - sx) + b * sx) * (1 - sy) + (c * (1 - sx) + d * sx) * sy;
}

std::uint32_t packRgb(double r, double g, double b) noexcept {
  const auto c = [](double v) { return static_cast<std::uint32_t>(std::clamp(v, 0.0, 255.0) + 0.5); };
  return c(r) | (c(g) << 8) | (c(b) << 16) | 0xFF000000u;
}

}  // namespace

std::unique_ptr<MemoryTerrain> makeSyntheticTerrain(const SyntheticTerrainSpec& spec) {
  if (spec.sizeVox < 4 || spec.sizeVox > 16384) {
    throw std::invalid_argument("makeSyntheticTerrain: size must be 4..16384 voxels, got " +
                                std::to_string(spec.sizeVox));
  }
  TerrainGeometry g;
  g.widthVox = spec.sizeVox;
  g.heightVox = spec.sizeVox;
  g.spacingM = spec.spacingM;
  g.originM = {0.0, 0.0};
  g.heightBaseM = 0.0;
  g.heightStepM = 0.05;
  g.tileShift = spec.tileShift;
  g.levels = 0;
  const auto n = static_cast<std::size_t>(spec.sizeVox) * static_cast<std::size_t>(spec.sizeVox);
  std::vector<std::uint16_t> heights(n);
  std::vector<std::uint32_t> colours(n);
  for (int j = 0; j < spec.sizeVox; ++j) {
    for (int i = 0; i < spec.sizeVox; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(spec.sizeVox) + i;
      const double fine = unitNoise(i, j, spec.seed + 7);  // per-voxel texture
      if (spec.kind == SyntheticKind::FlatPlane) {
        heights[k] = 0;
        const double smooth = 127.5 + 60.0 * std::sin(i * 0.05) * std::cos(j * 0.031);
        const double checker = ((i + j) & 1) ? 50.0 : -50.0;
        const double v = smooth + checker;
        colours[k] = packRgb(v, v * 0.9 + 10.0, v * 0.8 + 20.0);
        continue;
      }
      double h = 0.0;
      double amplitude = 1.0;
      double cell = 256.0;
      for (int octave = 0; octave < 6; ++octave) {
        h += amplitude * valueNoise(i, j, cell, spec.seed + static_cast<std::uint32_t>(octave));
        amplitude *= 0.5;
        cell *= 0.5;
      }
      h /= 1.96875;                        // sum of amplitudes: h in [0, 1]
      const double ridge = h * h * 420.0;  // metres, valleys flatter than peaks
      heights[k] = static_cast<std::uint16_t>(std::lround(ridge / g.heightStepM));
      // Elevation palette (green valleys, brown slopes, grey tops) with texture.
      const double e = ridge / 420.0;
      const double t = 0.75 + 0.5 * fine;
      const double r = (60 + 140 * e) * t;
      const double gr = (110 + 60 * e - 40 * e * e) * t;
      const double b = (50 + 120 * e * e) * t;
      colours[k] = packRgb(r, gr, b);
    }
  }
  return std::make_unique<MemoryTerrain>(g, heights, colours);
}

}  // namespace fieldcast::core
