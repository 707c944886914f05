#pragma once
// One pixel of the fixed-point bilinear sampling every fast kernel shares: the scalar reference
// of the vector kernel (ResampleLanes.cpp), which must produce the same bytes and count the same
// violations.

#include <algorithm>
#include <cstdint>

namespace fieldcast::warp::sampling {

constexpr int kFracBits = 8;  // 1/256 px: ≤ ½ grey level of position error at 255 levels/px
constexpr int kOne = 1 << kFracBits;

/// The frame a row samples: its bytes, row stride, size in pixels.
struct Source {
  const std::uint8_t* base;
  std::int32_t strideBytes;
  int widthPx, heightPx;
};

/// Samples `C` channels of `src` at frame pixel (px, py) into `out`; returns 1 for a margin
/// violation (outside [0, W] × [0, H], or NaN: clamped to the nearest edge, NaN to 0).
template <int C>
inline std::uint32_t samplePixel(const Source& src, float px, float py, std::uint8_t* out) noexcept {
  const auto w = static_cast<float>(src.widthPx), h = static_cast<float>(src.heightPx);
  const unsigned inside = static_cast<unsigned>(px >= 0.0f) & static_cast<unsigned>(px <= w) &
                          static_cast<unsigned>(py >= 0.0f) & static_cast<unsigned>(py <= h);
  // Pixel-centre origin, clamped; written so that NaN clamps to 0 (comparisons with NaN are false)
  float qx = px - 0.5f, qy = py - 0.5f;
  qx = qx >= 0.0f ? qx : 0.0f;
  qy = qy >= 0.0f ? qy : 0.0f;
  qx = std::min(qx, static_cast<float>(src.widthPx - 1));
  qy = std::min(qy, static_cast<float>(src.heightPx - 1));
  const auto ix = static_cast<std::int32_t>(qx * kOne + 0.5f);
  const auto iy = static_cast<std::int32_t>(qy * kOne + 0.5f);
  // The last column/row samples its left/upper neighbour with weight 0
  const std::int32_t x0 = std::min(ix >> kFracBits, src.widthPx - 2);
  const std::int32_t y0 = std::min(iy >> kFracBits, src.heightPx - 2);
  const std::int32_t fx = ix - (x0 << kFracBits);
  const std::int32_t fy = iy - (y0 << kFracBits);
  const std::uint8_t* p0 = src.base + y0 * src.strideBytes + x0 * C;
  const std::uint8_t* p1 = p0 + src.strideBytes;
  for (int c = 0; c < C; ++c) {
    // Blend along x on both rows, then along y
    const int top = p0[c] * (kOne - fx) + p0[C + c] * fx;
    const int bottom = p1[c] * (kOne - fx) + p1[C + c] * fx;
    out[c] =
        static_cast<std::uint8_t>((top * (kOne - fy) + bottom * fy + (1 << (2 * kFracBits - 1))) >> (2 * kFracBits));
  }
  return 1u - inside;
}

/// A row of `n` samples, pixel by pixel.
template <int C>
inline std::uint32_t sampleRowScalar(const Source& src, const float* xs, const float* ys, int n,
                                     std::uint8_t* dst) noexcept {
  std::uint32_t violations = 0;
  for (int i = 0; i < n; ++i) violations += samplePixel<C>(src, xs[i], ys[i], dst + i * C);
  return violations;
}

/// The vector kernel at the dispatched SIMD level (ResampleLanes.cpp); `channels` 1 or 3.
std::uint32_t sampleRowLanes(const Source& src, int channels, const float* xs, const float* ys, int n,
                             std::uint8_t* dst) noexcept;

}  // namespace fieldcast::warp::sampling
