#pragma once
// The AGC's measure: BT.601 luma summed along a row, the scalar reference of the vector kernel
// (LumaSumLanes.cpp), which must give the same sums.

#include <cstdint>

namespace fieldcast::warp::luma {

/// BT.601 luma weights in 1/256 (0.299, 0.587, 0.114): they sum to exactly 256.
constexpr int kWr = 77, kWg = 150, kWb = 29;

/// The luma (0..255) of an R'G'B' pixel.
inline int lumaOf(const std::uint8_t* p) noexcept { return (kWr * p[0] + kWg * p[1] + kWb * p[2]) >> 8; }

/// The sum of the luma of pixels 0, step, 2·step, ... of `widthPx` pixels of R'G'B' (`channels` 3)
/// or grey (1).
inline std::uint64_t lumaSumRowScalar(const std::uint8_t* row, int channels, int widthPx, int step) noexcept {
  std::uint64_t sum = 0;
  for (int x = 0; x < widthPx; x += step) {
    const std::uint8_t* p = row + x * channels;
    sum += static_cast<std::uint64_t>(channels == 3 ? lumaOf(p) : p[0]);
  }
  return sum;
}

/// The widest row the lanes sum: 255 a pixel stays within their 31-bit totals.
constexpr int kMaxLanesRowPx = 1 << 22;

/// lumaSumRowScalar of an R'G'B' row with step 1, or 2 when `everyOther`, in SIMD lanes at the
/// dispatched level. Rows of up to kMaxLanesRowPx pixels.
std::uint64_t rgbLumaSumRowLanes(const std::uint8_t* row, int widthPx, bool everyOther) noexcept;

}  // namespace fieldcast::warp::luma
