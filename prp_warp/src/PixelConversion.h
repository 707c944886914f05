#pragma once
// One row of gain and RGB → UYVY 4:2:2: the scalar reference of the vector kernel
// (PixelConversionLanes.cpp), which must produce the same bytes.

#include <fieldcast/Image.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

namespace fieldcast::warp::conversion {

/// Unity gain in the 1/65536 steps of AutoGain::gainQ16().
constexpr std::int32_t kUnityGain = 1 << 16;
/// The largest gain applied, 128: 255 times it, plus the rounding, stays within 32 bits.
constexpr std::int32_t kMaxGain = 128 << 16;

/// A gain as applied: within [0, kMaxGain].
inline std::int32_t validGain(std::int32_t gainQ16) noexcept { return std::clamp(gainQ16, 0, kMaxGain); }

/// An 8-bit value times a gain in 1/65536 (within [0, kMaxGain]), rounded half up, clipped at 255.
inline int applyGain(int value, std::int32_t gainQ16) noexcept {
  return std::min((value * gainQ16 + (1 << 15)) >> 16, 255);
}

/// Every 8-bit value under a gain, as a table: entry v is applyGain(v, gainQ16).
inline void fillGainTable(std::int32_t gainQ16, std::array<std::uint8_t, 256>& table) noexcept {
  for (int v = 0; v < 256; ++v) table[static_cast<std::size_t>(v)] = static_cast<std::uint8_t>(applyGain(v, gainQ16));
}

/// BT.601 video-range Y'CbCr of an R'G'B' triple, in 1/2^16 fixed point.
struct YCbCr {
  int y, cb, cr;
};
inline YCbCr toVideoRange(int r, int g, int b) noexcept {
  // Coefficients: 219/255 · (0.299, 0.587, 0.114) and 224/255 · (Cb, Cr rows of BT.601), × 65536.
  const int y = 16 * 65536 + 16829 * r + 33039 * g + 6416 * b;
  const int cb = 128 * 65536 - 9714 * r - 19070 * g + 28784 * b;
  const int cr = 128 * 65536 + 28784 * r - 24103 * g - 4681 * b;
  return {y, cb, cr};
}

/// `widthPx` (even) pixels of R'G'B' (or grey when `channels` is 1) under a gain into UYVY: per
/// pair Cb, Y0, Cr, Y1, the chroma the mean of both pixels' (a 2-tap decimation filter). No clamp
/// needed: for 8-bit inputs these roundings stay within Y 16..235 and C 16..240.
inline void toUyvyRowScalar(const std::uint8_t* in, int channels, int widthPx, std::int32_t gainQ16,
                            std::uint8_t* out) noexcept {
  const int g = channels == 3 ? 1 : 0, b = channels == 3 ? 2 : 0;
  for (int x = 0; x + 1 < widthPx; x += 2) {
    const std::uint8_t* p = in + x * channels;
    const std::uint8_t* q = p + channels;
    const YCbCr p0 = toVideoRange(applyGain(p[0], gainQ16), applyGain(p[g], gainQ16), applyGain(p[b], gainQ16));
    const YCbCr p1 = toVideoRange(applyGain(q[0], gainQ16), applyGain(q[g], gainQ16), applyGain(q[b], gainQ16));
    constexpr int kHalf = 1 << 15;
    out[2 * x + 0] = static_cast<std::uint8_t>((p0.cb + p1.cb + 2 * kHalf) >> 17);
    out[2 * x + 1] = static_cast<std::uint8_t>((p0.y + kHalf) >> 16);
    out[2 * x + 2] = static_cast<std::uint8_t>((p0.cr + p1.cr + 2 * kHalf) >> 17);
    out[2 * x + 3] = static_cast<std::uint8_t>((p1.y + kHalf) >> 16);
  }
}

/// toUyvyRowScalar for R'G'B' rows in SIMD lanes at the dispatched level.
void rgbToUyvyRowLanes(const std::uint8_t* in, int widthPx, std::int32_t gainQ16, std::uint8_t* out) noexcept;

/// `widthPx` pixels of R'G'B' or grey (`inFormat`) under a gain to `outFormat` (R'G'B', grey
/// luma, or UYVY: then `widthPx` even): convertPixels' rows, and the field warper's pieces of
/// rows. `lanes` picks the vector kernel where there is one. RT-safe.
void convertRow(const std::uint8_t* in, PixelFormat inFormat, int widthPx, PixelFormat outFormat, std::int32_t gainQ16,
                bool lanes, std::uint8_t* out) noexcept;

}  // namespace fieldcast::warp::conversion
