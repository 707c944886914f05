#pragma once
// Pixel colour shared by the fast caster and the reference renderer: terrain colour with the
// next level blended in, haze toward the horizon colour with range, the sky gradient, and what a
// ray that misses the terrain sees (the base plane beyond the edge, or the sky).

#include "TerrainLight.h"

#include <ig_core/RenderSettings.h>

#include <fieldcast/Image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace fieldcast::core {

/// Four floats in one SSE register (GCC/Clang vector extension).
using Float4 = float __attribute__((vector_size(16)));

/// Linear RGB in 0..255 (float): what a ray contributes to its pixel. Held as four floats (the
/// fourth is unused), so unpacking, mixing and storing a colour are a few vector instructions.
struct Rgb {
  Float4 v{0.0f, 0.0f, 0.0f, 0.0f};
  Rgb() noexcept = default;
  explicit Rgb(Float4 x) noexcept : v(x) {}
  Rgb(float r, float g, float b) noexcept : v{r, g, b, 0.0f} {}
  Rgb& operator+=(const Rgb& o) noexcept {
    v += o.v;
    return *this;
  }
};

/// RGBA8 (R in the low byte) to Rgb; alpha lands in the unused fourth lane.
inline Rgb unpackRgb(std::uint32_t rgba) noexcept {
#if defined(__SSE2__)
  // Zero-extend the bytes to 32-bit lanes, convert: four instructions (the generic conversion
  // below compiles to four scalar conversions).
  const __m128i zero = _mm_setzero_si128();
  const __m128i bytes = _mm_cvtsi32_si128(static_cast<int>(rgba));
  return Rgb{Float4(_mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_unpacklo_epi8(bytes, zero), zero)))};
#else
  using Bytes4 = std::uint8_t __attribute__((vector_size(4)));
  Bytes4 bytes;
  std::memcpy(&bytes, &rgba, sizeof bytes);
  return Rgb{__builtin_convertvector(bytes, Float4)};
#endif
}
inline Rgb mix(const Rgb& a, const Rgb& b, float t) noexcept { return Rgb{a.v + (b.v - a.v) * t}; }

/// Range (metres) at which a ray that missed the terrain meets the base plane, the flat world
/// beyond the database's edge (RENDERER.md, "Beyond the edge"), for a camera `aboveM` over the
/// plane and a ray of world z `dz` and length `length` per metre of depth; infinite when it never
/// does (level or climbing, or the camera not above the plane): then it sees the sky.
inline double basePlaneRangeM(double aboveM, double dz, double length) noexcept {
  return dz < 0.0 && aboveM > 0.0 ? aboveM * length / -dz : std::numeric_limits<double>::infinity();
}

/// Haze and the pixel store as a small value: hot loops keep it in registers. (Their pixel stores
/// are bytes, which may alias anything, so members read through a reference would be read again
/// after every pixel.) The haze table it points to belongs to the Shading that made it.
struct PixelShader {
  const float* haze;  ///< haze fraction 1 − exp(−r/R) per table step
  float invStepM;     ///< table steps per metre of range
  float lastStep;     ///< the table's last index
  Rgb horizon;        ///< haze colour
  bool hazeOn;
  bool grey;

  /// Terrain colour at range `rangeM` (metres). RT-safe.
  Rgb terrain(const Rgb& colour, float rangeM) const noexcept {
    if (!hazeOn) return colour;
    const float steps = rangeM * invStepM;
    const float x = steps < lastStep ? steps : lastStep;  // a NaN range reads the last entry
    return mix(colour, horizon, haze[static_cast<std::size_t>(x)]);
  }

  /// Writes `c` × `scale` (the mean of the sub-ray colours) to the pixel at `pixel`. RT-safe.
  void storePixel(std::uint8_t* pixel, const Rgb& c, float scale) const noexcept {
    // Clamp to 0..255 and round, all lanes at once.
    const Float4 zero{0.0f, 0.0f, 0.0f, 0.0f};
    const Float4 top{255.0f, 255.0f, 255.0f, 255.0f};
    Float4 x;
    if (grey) {
      const Float4 w = c.v * Float4{0.299f, 0.587f, 0.114f, 0.0f};  // BT.601 luma
      x = Float4{(w[0] + w[1] + w[2]) * scale, 0.0f, 0.0f, 0.0f};
    } else {
      x = c.v * scale;
    }
#if defined(__SSE2__)
    // Clamp, round and narrow to bytes in registers; one 16-bit store and one byte store.
    const __m128 clamped = _mm_min_ps(_mm_max_ps(__m128(x), __m128(zero)), __m128(top));
    const __m128i ints = _mm_cvttps_epi32(_mm_add_ps(clamped, _mm_set1_ps(0.5f)));
    const auto packed =
        static_cast<std::uint32_t>(_mm_cvtsi128_si32(_mm_packus_epi16(_mm_packs_epi32(ints, ints), ints)));
    pixel[0] = static_cast<std::uint8_t>(packed);
    if (!grey) {
      const auto gb = static_cast<std::uint16_t>(packed >> 8);
      std::memcpy(pixel + 1, &gb, sizeof gb);
    }
#else
    using Int4 = int __attribute__((vector_size(16)));
    x = x > zero ? x : zero;
    x = x < top ? x : top;
    const Int4 i = __builtin_convertvector(x + 0.5f, Int4);
    pixel[0] = static_cast<std::uint8_t>(i[0]);
    if (!grey) {
      pixel[1] = static_cast<std::uint8_t>(i[1]);
      pixel[2] = static_cast<std::uint8_t>(i[2]);
    }
#endif
  }
};

/// Haze, sky and light for one frame's settings. Built once per frame (a small table); RT-safe to
/// use. The sky and the haze colour are dimmed by the daylight the frame's sun leaves.
class Shading {
 public:
  explicit Shading(const RenderSettings& s) noexcept
      : mLight(s),
        mZenith{Float4{static_cast<float>(s.skyZenithRgb.x), static_cast<float>(s.skyZenithRgb.y),
                       static_cast<float>(s.skyZenithRgb.z), 0.0f} *
                mLight.sky()},
        mHorizon{Float4{static_cast<float>(s.skyHorizonRgb.x), static_cast<float>(s.skyHorizonRgb.y),
                        static_cast<float>(s.skyHorizonRgb.z), 0.0f} *
                 mLight.sky()},
        mGrey(s.colourMode == FrameColour::Grey) {
    // Haze fraction 1 − exp(−r/R) tabulated over [0, 8R]: a table lookup per pixel instead of exp.
    mHazeOn = s.hazeRangeM > 0.0;
    const double maxRange = mHazeOn ? 8.0 * s.hazeRangeM : 1.0;
    mInvStepM = static_cast<float>((kTable - 1) / maxRange);
    for (int k = 0; k < kTable; ++k) {
      const double r = k / static_cast<double>(mInvStepM);
      mHaze[static_cast<std::size_t>(k)] = mHazeOn ? static_cast<float>(1.0 - std::exp(-r / s.hazeRangeM)) : 0.0f;
    }
  }
  Shading(const Shading&) = delete;  // PixelShaders point into the table
  Shading& operator=(const Shading&) = delete;

  /// The per-pixel part, as a value for hot loops.
  PixelShader pixelShader() const noexcept {
    return PixelShader{mHaze.data(), mInvStepM, static_cast<float>(kTable - 1), mHorizon, mHazeOn, mGrey};
  }

  /// Terrain colour at range `rangeM` (metres). RT-safe.
  Rgb terrain(const Rgb& colour, float rangeM) const noexcept { return pixelShader().terrain(colour, rangeM); }

  /// Sky colour for a ray whose elevation sine is `sinElevation`. RT-safe.
  Rgb sky(float sinElevation) const noexcept {
    const float t = std::sqrt(std::clamp(sinElevation, 0.0f, 1.0f));
    return mix(mHorizon, mZenith, t);
  }

  /// What a ray that missed the terrain sees: the base plane (colour `base`) at `rangeM`, in the
  /// haze, or the sky when the range is infinite. RT-safe.
  Rgb missed(const Rgb& base, float rangeM, float sinElevation) const noexcept {
    return rangeM < std::numeric_limits<float>::infinity() ? terrain(base, rangeM) : sky(sinElevation);
  }

  bool grey() const noexcept { return mGrey; }
  /// The frame's sun against the colours' (TerrainLight.h).
  const TerrainLight& light() const noexcept { return mLight; }

  /// Writes `c` × `scale` (the mean of the sub-ray colours) to the pixel at `pixel`. RT-safe.
  void storePixel(std::uint8_t* pixel, const Rgb& c, float scale) const noexcept {
    pixelShader().storePixel(pixel, c, scale);
  }
  /// Writes `c` × `scale` to pixel `u` of `row`. RT-safe.
  void store(std::uint8_t* row, int u, const Rgb& c, float scale) const noexcept {
    storePixel(row + (mGrey ? u : 3 * u), c, scale);
  }
  /// Bytes per pixel of the output.
  int bytesPerPixel() const noexcept { return mGrey ? 1 : 3; }

 private:
  static constexpr int kTable = 1024;
  TerrainLight mLight;
  Rgb mZenith;
  Rgb mHorizon;
  bool mGrey;
  bool mHazeOn = false;
  float mInvStepM = 1.0f;
  std::array<float, kTable> mHaze{};
};

}  // namespace fieldcast::core
