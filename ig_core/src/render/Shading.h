#pragma once
// Pixel colour shared by the fast caster and the reference renderer: terrain colour with the
// next level blended in, haze toward the horizon colour with range, and the sky gradient.

#include <ig_core/RenderSettings.h>

#include <fieldcast/Image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace fieldcast::core {

/// Linear RGB in 0..255 (float): what a ray contributes to its pixel.
struct Rgb {
  float r = 0, g = 0, b = 0;
};

inline Rgb unpackRgb(std::uint32_t rgba) noexcept {
  return {static_cast<float>(rgba & 0xFFu), static_cast<float>((rgba >> 8) & 0xFFu),
          static_cast<float>((rgba >> 16) & 0xFFu)};
}
inline Rgb mix(const Rgb& a, const Rgb& b, float t) noexcept {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}

/// Haze and sky for one frame's settings. Built once per frame (a small table); RT-safe to use.
class Shading {
 public:
  explicit Shading(const RenderSettings& s) noexcept
      : mZenith{static_cast<float>(s.skyZenithRgb.x), static_cast<float>(s.skyZenithRgb.y),
                static_cast<float>(s.skyZenithRgb.z)},
        mHorizon{static_cast<float>(s.skyHorizonRgb.x), static_cast<float>(s.skyHorizonRgb.y),
                 static_cast<float>(s.skyHorizonRgb.z)},
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

  /// Terrain colour at range `rangeM` (metres). RT-safe.
  Rgb terrain(const Rgb& colour, float rangeM) const noexcept {
    if (!mHazeOn) return colour;
    const float x = std::min(rangeM * mInvStepM, static_cast<float>(kTable - 1));
    return mix(colour, mHorizon, mHaze[static_cast<std::size_t>(x)]);
  }

  /// Sky colour for a ray whose elevation sine is `sinElevation`. RT-safe.
  Rgb sky(float sinElevation) const noexcept {
    const float t = std::sqrt(std::clamp(sinElevation, 0.0f, 1.0f));
    return mix(mHorizon, mZenith, t);
  }

  bool grey() const noexcept { return mGrey; }

  /// Writes `c` × `scale` (the mean of the sub-ray colours) to the pixel at `pixel`. RT-safe.
  void storePixel(std::uint8_t* pixel, const Rgb& c, float scale) const noexcept {
    // max then min: maxss/minss, no branches in the per-pixel path.
    const auto byte = [](float v) { return static_cast<std::uint8_t>(std::min(std::max(v, 0.0f), 255.0f) + 0.5f); };
    if (mGrey) {
      pixel[0] = byte((0.299f * c.r + 0.587f * c.g + 0.114f * c.b) * scale);
    } else {
      pixel[0] = byte(c.r * scale);
      pixel[1] = byte(c.g * scale);
      pixel[2] = byte(c.b * scale);
    }
  }
  /// Writes `c` × `scale` to pixel `u` of `row`. RT-safe.
  void store(std::uint8_t* row, int u, const Rgb& c, float scale) const noexcept {
    storePixel(row + (mGrey ? u : 3 * u), c, scale);
  }
  /// Bytes per pixel of the output.
  int bytesPerPixel() const noexcept { return mGrey ? 1 : 3; }

 private:
  static constexpr int kTable = 1024;
  Rgb mZenith;
  Rgb mHorizon;
  bool mGrey;
  bool mHazeOn = false;
  float mInvStepM = 1.0f;
  std::array<float, kTable> mHaze{};
};

}  // namespace fieldcast::core
