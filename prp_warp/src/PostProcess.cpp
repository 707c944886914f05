// Field post-processing: AGC, flicker filter, pixel format conversion (ITU-R BT.601 coefficients).
#include <prp_warp/PostProcess.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace fieldcast::warp {
namespace {

// BT.601 luma weights in 1/256 (0.299, 0.587, 0.114) sum to exactly 256.
constexpr int kWr = 77, kWg = 150, kWb = 29;

std::uint8_t clampByte(int v) noexcept { return static_cast<std::uint8_t>(std::clamp(v, 0, 255)); }

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

}  // namespace

AutoGain::AutoGain(const AutoGainConfig& config) noexcept : mConfig(config) { rebuildTable(); }

void AutoGain::reset() noexcept {
  mGain = 1.0;
  rebuildTable();
}

void AutoGain::rebuildTable() noexcept {
  for (int i = 0; i < 256; ++i)
    mTable[static_cast<std::size_t>(i)] = clampByte(static_cast<int>(std::lround(i * mGain)));
  mTableGain = mGain;
}

double meanLuma(const Image& image, int step) noexcept {
  if (image.empty() || step < 1) return 0.0;
  const int ch = image.format() == PixelFormat::Rgb8 ? 3 : 1;
  if (image.format() == PixelFormat::Uyvy422) return 0.0;
  std::uint64_t sum = 0, count = 0;
  for (int y = 0; y < image.heightPx(); y += step) {
    const std::uint8_t* row = image.row(y);
    for (int x = 0; x < image.widthPx(); x += step) {
      const std::uint8_t* p = row + x * ch;
      sum += ch == 3 ? static_cast<std::uint64_t>((kWr * p[0] + kWg * p[1] + kWb * p[2]) >> 8) : p[0];
      ++count;
    }
  }
  return count ? static_cast<double>(sum) / static_cast<double>(count) : 0.0;
}

void AutoGain::process(Image& field, Nanoseconds elapsed) noexcept {
  if (!mConfig.enabled || field.empty() || field.format() == PixelFormat::Uyvy422) return;
  // A sparse sample of the field is plenty for a mean: every 2nd pixel of every 2nd row
  const double mean = meanLuma(field, 2);
  const double wanted = std::clamp(mConfig.targetMeanLevel / std::max(mean, 1.0), mConfig.minGain, mConfig.maxGain);
  const double dt = std::max(0.0, toSeconds(elapsed));
  const double alpha = mConfig.timeConstantS > 0.0 ? 1.0 - std::exp(-dt / mConfig.timeConstantS) : 1.0;
  mGain += alpha * (wanted - mGain);
  if (std::abs(mGain - mTableGain) > 1e-4) rebuildTable();
  for (std::uint8_t& b : field.bytes()) b = mTable[b];
}

bool flickerFilter(const Image& src, Image& dst) noexcept {
  if (src.format() == PixelFormat::Uyvy422 || dst.format() != src.format() || dst.widthPx() != src.widthPx() ||
      dst.heightPx() != src.heightPx() || src.empty())
    return false;
  const int h = src.heightPx();
  const auto n = static_cast<int>(src.strideBytes());
  for (int y = 0; y < h; ++y) {
    // Edge rows repeat themselves
    const std::uint8_t* above = src.row(std::max(y - 1, 0));
    const std::uint8_t* here = src.row(y);
    const std::uint8_t* below = src.row(std::min(y + 1, h - 1));
    std::uint8_t* out = dst.row(y);
    for (int i = 0; i < n; ++i) out[i] = static_cast<std::uint8_t>((above[i] + 2 * here[i] + below[i] + 2) >> 2);
  }
  return true;
}

bool convertPixels(const Image& src, Image& dst) noexcept {
  if (src.widthPx() != dst.widthPx() || src.heightPx() != dst.heightPx()) return false;
  if (src.format() == PixelFormat::Uyvy422) return false;
  const bool rgb = src.format() == PixelFormat::Rgb8;
  const int w = src.widthPx();
  for (int y = 0; y < src.heightPx(); ++y) {
    const std::uint8_t* in = src.row(y);
    std::uint8_t* out = dst.row(y);
    switch (dst.format()) {
      case PixelFormat::Rgb8:
        if (rgb) {
          std::memcpy(out, in, src.strideBytes());
        } else {
          for (int x = 0; x < w; ++x) out[3 * x] = out[3 * x + 1] = out[3 * x + 2] = in[x];
        }
        break;
      case PixelFormat::Grey8:
        if (rgb) {
          for (int x = 0; x < w; ++x)
            out[x] =
                static_cast<std::uint8_t>((kWr * in[3 * x] + kWg * in[3 * x + 1] + kWb * in[3 * x + 2] + 128) >> 8);
        } else {
          std::memcpy(out, in, src.strideBytes());
        }
        break;
      case PixelFormat::Uyvy422:
        for (int x = 0; x + 1 < w; x += 2) {
          int r0, g0, b0, r1, g1, b1;
          if (rgb) {
            r0 = in[3 * x], g0 = in[3 * x + 1], b0 = in[3 * x + 2];
            r1 = in[3 * x + 3], g1 = in[3 * x + 4], b1 = in[3 * x + 5];
          } else {
            r0 = g0 = b0 = in[x];
            r1 = g1 = b1 = in[x + 1];
          }
          const YCbCr p0 = toVideoRange(r0, g0, b0), p1 = toVideoRange(r1, g1, b1);
          constexpr int kHalf = 1 << 15;
          // Chroma of the pair: the mean of both pixels (a 2-tap decimation filter). No clamp
          // needed: for 8-bit inputs these roundings stay within Y 16..235 and C 16..240.
          out[2 * x + 0] = static_cast<std::uint8_t>((p0.cb + p1.cb + 2 * kHalf) >> 17);
          out[2 * x + 1] = static_cast<std::uint8_t>((p0.y + kHalf) >> 16);
          out[2 * x + 2] = static_cast<std::uint8_t>((p0.cr + p1.cr + 2 * kHalf) >> 17);
          out[2 * x + 3] = static_cast<std::uint8_t>((p1.y + kHalf) >> 16);
        }
        break;
    }
  }
  return true;
}

void mirrorInPlace(Image& image, Mirror mirror) noexcept {
  const int w = image.widthPx(), h = image.heightPx();
  const std::size_t pixelBytes = image.format() == PixelFormat::Rgb8 ? 3 : 1;
  if (mirrorsColumns(mirror)) {
    for (int y = 0; y < h; ++y) {
      std::uint8_t* row = image.row(y);
      for (int l = 0, r = w - 1; l < r; ++l, --r) {
        std::swap_ranges(row + l * pixelBytes, row + (l + 1) * pixelBytes, row + r * pixelBytes);
      }
    }
  }
  if (mirrorsRows(mirror)) {
    for (int top = 0, bottom = h - 1; top < bottom; ++top, --bottom) {
      std::swap_ranges(image.row(top), image.row(top) + image.strideBytes(), image.row(bottom));
    }
  }
}

void fillBlack(Image& image) noexcept {
  if (image.format() != PixelFormat::Uyvy422) {
    std::fill(image.bytes().begin(), image.bytes().end(), std::uint8_t{0});
    return;
  }
  std::span<std::uint8_t> b = image.bytes();
  for (std::size_t i = 0; i + 1 < b.size(); i += 2) {
    b[i] = 128;     // Cb or Cr
    b[i + 1] = 16;  // Y
  }
}

}  // namespace fieldcast::warp
