#pragma once
// Seeded 2D gradient noise (Perlin's improved noise with hashed gradients) and its sums, for the
// built-in terrain and the procedural colour. Pure functions of (x, y, seed): every thread count
// and every run gives the same terrain.

#include <cmath>
#include <cstdint>

namespace fieldcast::core::detail {

/// A well-mixed 32-bit hash of a lattice point and a seed.
inline std::uint32_t hashLattice(int x, int y, std::uint32_t seed) noexcept {
  std::uint32_t h =
      seed ^ (static_cast<std::uint32_t>(x) * 0x8DA6B343u) ^ (static_cast<std::uint32_t>(y) * 0xD8163841u);
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return h;
}

/// Uniform value in [0, 1) from a hash.
inline float unitFromHash(std::uint32_t h) noexcept { return static_cast<float>(h >> 8) * (1.0f / 16777216.0f); }

/// Gradient noise in about [-1, 1], zero at lattice points, C² (quintic fade).
inline float gradientNoise(float x, float y, std::uint32_t seed) noexcept {
  const float fx0 = std::floor(x);
  const float fy0 = std::floor(y);
  const int ix = static_cast<int>(fx0);
  const int iy = static_cast<int>(fy0);
  const float dx = x - fx0;
  const float dy = y - fy0;
  // Dot product of the offset with one of eight gradients chosen by the hash (a table, not a
  // switch: the hash is random, so a branch per corner would mispredict half the time).
  static constexpr float kGx[8] = {1.0f, -1.0f, 0.0f, 0.0f, 0.70710678f, 0.70710678f, -0.70710678f, -0.70710678f};
  static constexpr float kGy[8] = {0.0f, 0.0f, 1.0f, -1.0f, 0.70710678f, -0.70710678f, 0.70710678f, -0.70710678f};
  const auto corner = [seed](int cx, int cy, float ox, float oy) noexcept {
    const std::uint32_t g = hashLattice(cx, cy, seed) & 7u;
    return kGx[g] * ox + kGy[g] * oy;
  };
  const float n00 = corner(ix, iy, dx, dy);
  const float n10 = corner(ix + 1, iy, dx - 1.0f, dy);
  const float n01 = corner(ix, iy + 1, dx, dy - 1.0f);
  const float n11 = corner(ix + 1, iy + 1, dx - 1.0f, dy - 1.0f);
  const auto fade = [](float t) noexcept { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); };
  const float u = fade(dx);
  const float v = fade(dy);
  const float nx0 = n00 + u * (n10 - n00);
  const float nx1 = n01 + u * (n11 - n01);
  return 1.4142f * (nx0 + v * (nx1 - nx0));
}

/// Fractal sum of `octaves` gradient noises, each at twice the frequency and `gain` the
/// amplitude of the last, rotated between octaves so the lattice does not line up. About [-1, 1].
inline float fbm(float x, float y, int octaves, std::uint32_t seed, float gain = 0.5f) noexcept {
  float sum = 0.0f;
  float amplitude = 1.0f;
  float norm = 0.0f;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * gradientNoise(x, y, seed + static_cast<std::uint32_t>(o) * 0x9E3779B9u);
    norm += amplitude;
    amplitude *= gain;
    // Rotate by ~36.87° (3-4-5 triangle) and double the frequency.
    const float rx = 1.6f * x - 1.2f * y;
    const float ry = 1.2f * x + 1.6f * y;
    x = rx + 17.3f;
    y = ry - 9.1f;
  }
  return sum / norm;
}

/// Ridged multifractal in [0, 1]: sharp crests where the noise crosses zero, smoother valleys;
/// each octave is weighted by the one before so detail gathers on the ridges (Musgrave).
inline float ridged(float x, float y, int octaves, std::uint32_t seed) noexcept {
  float sum = 0.0f;
  float amplitude = 1.0f;
  float norm = 0.0f;
  float weight = 1.0f;
  for (int o = 0; o < octaves; ++o) {
    float r = 1.0f - std::fabs(gradientNoise(x, y, seed + static_cast<std::uint32_t>(o) * 0x9E3779B9u));
    r *= r;
    r *= weight;
    weight = std::fmin(1.0f, std::fmax(0.0f, 1.8f * r));
    sum += amplitude * r;
    norm += amplitude;
    amplitude *= 0.5f;
    const float rx = 1.6f * x - 1.2f * y;
    const float ry = 1.2f * x + 1.6f * y;
    x = rx + 31.7f;
    y = ry + 5.3f;
  }
  return sum / norm;
}

/// Cubic Hermite smoothstep of x between edges a < b: 0 below a, 1 above b.
inline double smoothstep(double a, double b, double x) noexcept {
  double t = (x - a) / (b - a);
  t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace fieldcast::core::detail
