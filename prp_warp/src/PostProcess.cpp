// Field post-processing: AGC, flicker filter, pixel format conversion (ITU-R BT.601 coefficients).
#include <prp_warp/PostProcess.h>

#include "FlickerRow.h"
#include "LumaSum.h"
#include "PixelConversion.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace fieldcast::warp {
namespace {

using conversion::applyGain;
using luma::kWb;
using luma::kWg;
using luma::kWr;

// The mean of the row sums `rowSum(row, channels, widthPx)` of every `step`-th row
template <typename RowSum>
double meanOfRows(const Image& image, int step, RowSum&& rowSum) noexcept {
  if (image.empty() || step < 1) return 0.0;
  if (image.format() != PixelFormat::Rgb8 && image.format() != PixelFormat::Grey8) return 0.0;
  const int channels = image.format() == PixelFormat::Rgb8 ? 3 : 1;
  std::uint64_t sum = 0, count = 0;
  for (int y = 0; y < image.heightPx(); y += step) {
    sum += rowSum(image.row(y), channels, image.widthPx());
    count += static_cast<std::uint64_t>((image.widthPx() - 1) / step + 1);
  }
  return count ? static_cast<double>(sum) / static_cast<double>(count) : 0.0;
}

}  // namespace

AutoGain::AutoGain(const AutoGainConfig& config) noexcept : mConfig(config) { rebuildTable(); }

void AutoGain::reset() noexcept {
  mGain = 1.0;
  rebuildTable();
}

void AutoGain::rebuildTable() noexcept {
  mGainQ16 = static_cast<std::int32_t>(std::lround(std::clamp(mGain, 0.0, 128.0) * conversion::kUnityGain));
  conversion::fillGainTable(mGainQ16, mTable);
  mTableGain = mGain;
}

double meanLuma(const Image& image, int step) noexcept {
  return meanOfRows(image, step, [step](const std::uint8_t* row, int channels, int widthPx) {
    const bool lanes = channels == 3 && step <= 2 && widthPx <= luma::kMaxLanesRowPx;
    return lanes ? luma::rgbLumaSumRowLanes(row, widthPx, step == 2)
                 : luma::lumaSumRowScalar(row, channels, widthPx, step);
  });
}

double meanLumaReference(const Image& image, int step) noexcept {
  return meanOfRows(image, step, [step](const std::uint8_t* row, int channels, int widthPx) {
    return luma::lumaSumRowScalar(row, channels, widthPx, step);
  });
}

void AutoGain::process(Image& field, Nanoseconds elapsed) noexcept {
  if (!update(field, elapsed)) return;
  for (std::uint8_t& b : field.bytes()) b = mTable[b];
}

std::int32_t AutoGain::gainQ16() const noexcept { return mConfig.enabled ? mGainQ16 : conversion::kUnityGain; }

bool AutoGain::update(const Image& field, Nanoseconds elapsed) noexcept {
  if (!mConfig.enabled || field.empty() || field.format() == PixelFormat::Uyvy422) return false;
  // A sparse sample of the field is plenty for a mean: every 2nd pixel of every 2nd row
  return updateFromMean(meanLuma(field, 2), elapsed);
}

bool AutoGain::updateFromMean(double mean, Nanoseconds elapsed) noexcept {
  if (!mConfig.enabled) return false;
  const double wanted = std::clamp(mConfig.targetMeanLevel / std::max(mean, 1.0), mConfig.minGain, mConfig.maxGain);
  const double dt = std::max(0.0, toSeconds(elapsed));
  const double alpha = mConfig.timeConstantS > 0.0 ? 1.0 - std::exp(-dt / mConfig.timeConstantS) : 1.0;
  mGain += alpha * (wanted - mGain);
  if (std::abs(mGain - mTableGain) > 1e-4) rebuildTable();
  return true;
}

namespace {

bool filterRows(const Image& src, Image& dst, bool lanes) noexcept {
  if (src.format() == PixelFormat::Uyvy422 || !dst.sameShape(src) || src.empty()) return false;
  const int h = src.heightPx();
  const auto n = static_cast<int>(src.strideBytes());
  for (int y = 0; y < h; ++y) {
    // Edge rows repeat themselves
    const std::uint8_t* above = src.row(std::max(y - 1, 0));
    const std::uint8_t* below = src.row(std::min(y + 1, h - 1));
    if (lanes) {
      flicker::filterRowLanes(above, src.row(y), below, n, dst.row(y));
    } else {
      flicker::filterRowScalar(above, src.row(y), below, n, dst.row(y));
    }
  }
  return true;
}

}  // namespace

bool flickerFilter(const Image& src, Image& dst) noexcept { return filterRows(src, dst, true); }

bool flickerFilterReference(const Image& src, Image& dst) noexcept { return filterRows(src, dst, false); }

bool makeFlickerFiltered(Frame& frame) {
  frame.hasFlickerFiltered = false;
  const Image& image = frame.image;
  if (image.empty() || image.format() == PixelFormat::Uyvy422) return false;
  Image& copy = frame.flickerFiltered;
  // Resized (and so cleared) only when the frame's shape changed: the filter writes every byte
  if (!copy.sameShape(image)) copy.resize(image.widthPx(), image.heightPx(), image.format());
  frame.hasFlickerFiltered = flickerFilter(image, copy);
  return frame.hasFlickerFiltered;
}

namespace conversion {

void convertRow(const std::uint8_t* in, PixelFormat inFormat, int widthPx, PixelFormat outFormat, std::int32_t gainQ16,
                bool lanes, std::uint8_t* out) noexcept {
  gainQ16 = validGain(gainQ16);
  const bool rgb = inFormat == PixelFormat::Rgb8;
  const int channels = rgb ? 3 : 1;
  const int w = widthPx;
  const bool unity = gainQ16 == kUnityGain;
  switch (outFormat) {
    case PixelFormat::Rgb8:
      if (unity && rgb) {
        std::memcpy(out, in, rowBytes(inFormat, w));
        break;
      }
      for (int x = 0; x < 3 * w; ++x) out[x] = static_cast<std::uint8_t>(applyGain(in[rgb ? x : x / 3], gainQ16));
      break;
    case PixelFormat::Grey8:
      if (unity && !rgb) {
        std::memcpy(out, in, rowBytes(inFormat, w));
        break;
      }
      for (int x = 0; x < w; ++x) {
        const std::uint8_t* p = in + channels * x;
        const int luma = rgb ? (kWr * applyGain(p[0], gainQ16) + kWg * applyGain(p[1], gainQ16) +
                                kWb * applyGain(p[2], gainQ16) + 128) >>
                                   8
                             : applyGain(p[0], gainQ16);
        out[x] = static_cast<std::uint8_t>(luma);
      }
      break;
    case PixelFormat::Uyvy422:
      if (lanes && rgb) {
        rgbToUyvyRowLanes(in, w, gainQ16, out);
      } else {
        toUyvyRowScalar(in, channels, w, gainQ16, out);
      }
      break;
  }
}

}  // namespace conversion

namespace {

/// convertPixels' rows; `lanes` picks the vector kernel where there is one.
bool convertRows(const Image& src, Image& dst, std::int32_t gainQ16, bool lanes) noexcept {
  if (src.widthPx() != dst.widthPx() || src.heightPx() != dst.heightPx()) return false;
  if (src.format() == PixelFormat::Uyvy422) return false;
  for (int y = 0; y < src.heightPx(); ++y) {
    conversion::convertRow(src.row(y), src.format(), src.widthPx(), dst.format(), gainQ16, lanes, dst.row(y));
  }
  return true;
}

}  // namespace

bool convertPixels(const Image& src, Image& dst, std::int32_t gainQ16) noexcept {
  return convertRows(src, dst, gainQ16, true);
}

bool convertPixelsReference(const Image& src, Image& dst, std::int32_t gainQ16) noexcept {
  return convertRows(src, dst, gainQ16, false);
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
