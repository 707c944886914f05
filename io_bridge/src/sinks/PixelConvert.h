#pragma once
// Row conversions between the field pixel formats and what the outputs need. BT.601 video range
// ("studio swing", Y 16–235, Cb/Cr 16–240) in integer arithmetic, as in Rec. 601 and every
// video tool. 4:2:2 chroma is co-sited with the even luma samples (Rec. 601), so RGB rows are
// filtered [1 2 1]/4 around each even pixel before subsampling. All functions are RT-safe.

#include <fieldcast/Image.h>

#include <cstdint>

namespace fieldcast::io {

/// Converts one row of `widthPx` pixels from `format` to UYVY 4:2:2 (Cb Y0 Cr Y1). An odd width
/// (RGB or grey only) fills the last pair with a copy of the last pixel: (widthPx + 1) / 2 × 4 bytes.
void rowToUyvy(const std::uint8_t* src, PixelFormat format, int widthPx, std::uint8_t* uyvy) noexcept;

/// Splits a UYVY row into planar Y (widthPx bytes), Cb and Cr ((widthPx + 1) / 2 bytes each).
void uyvyToPlanar(const std::uint8_t* uyvy, int widthPx, std::uint8_t* y, std::uint8_t* cb, std::uint8_t* cr) noexcept;

/// Converts one row from `format` to 8-bit RGB (sRGB-encoded, full range); `bgr` swaps to B, G, R
/// (OpenCV order). UYVY chroma of odd pixels is interpolated from its neighbours.
void rowToRgb(const std::uint8_t* src, PixelFormat format, int widthPx, std::uint8_t* rgb, bool bgr = false) noexcept;

/// Averages two chroma rows (rounding half up): vertical 4:2:2 → 4:2:0 subsampling.
void averageRows(const std::uint8_t* a, const std::uint8_t* b, int count, std::uint8_t* out) noexcept;

/// BT.601 video-range luma and chroma of one full-range RGB pixel.
struct Ycbcr {
  std::uint8_t y, cb, cr;
};
Ycbcr rgbToYcbcr(int r, int g, int b) noexcept;

}  // namespace fieldcast::io
