// Integer BT.601 conversions (ITU-R BT.601-7, video range; the 8-bit coefficients of
// Jack, "Video Demystified").

#include "PixelConvert.h"

#include <algorithm>

namespace fieldcast::io {

namespace {

std::uint8_t clamp8(int v) noexcept { return static_cast<std::uint8_t>(std::clamp(v, 0, 255)); }

int lumaOf(int r, int g, int b) noexcept { return ((66 * r + 129 * g + 25 * b + 128) >> 8) + 16; }
int cbOf(int r, int g, int b) noexcept { return ((-38 * r - 74 * g + 112 * b + 128) >> 8) + 128; }
int crOf(int r, int g, int b) noexcept { return ((112 * r - 94 * g - 18 * b + 128) >> 8) + 128; }

// Fetches pixel x (clamped to the row) as RGB.
void rgbAt(const std::uint8_t* src, PixelFormat format, int widthPx, int x, int& r, int& g, int& b) noexcept {
  x = std::clamp(x, 0, widthPx - 1);
  if (format == PixelFormat::Grey8) {
    r = g = b = src[x];
  } else {
    const std::uint8_t* p = src + 3 * x;
    r = p[0];
    g = p[1];
    b = p[2];
  }
}

}  // namespace

Ycbcr rgbToYcbcr(int r, int g, int b) noexcept {
  return {clamp8(lumaOf(r, g, b)), clamp8(cbOf(r, g, b)), clamp8(crOf(r, g, b))};
}

void rowToUyvy(const std::uint8_t* src, PixelFormat format, int widthPx, std::uint8_t* uyvy) noexcept {
  if (format == PixelFormat::Uyvy422) {
    std::copy(src, src + 2 * widthPx, uyvy);
    return;
  }
  if (format == PixelFormat::Grey8) {
    // Grey is R = G = B: chroma is exactly neutral, luma is the RGB formula.
    for (int x = 0; x < widthPx; x += 2) {
      std::uint8_t* o = uyvy + 2 * x;
      o[0] = 128;
      o[1] = clamp8(((220 * src[x] + 128) >> 8) + 16);
      o[2] = 128;
      o[3] = clamp8(((220 * src[std::min(x + 1, widthPx - 1)] + 128) >> 8) + 16);
    }
    return;
  }
  for (int x = 0; x < widthPx; x += 2) {
    int r0, g0, b0, r1, g1, b1, rl, gl, bl;
    rgbAt(src, format, widthPx, x, r0, g0, b0);
    rgbAt(src, format, widthPx, x + 1, r1, g1, b1);
    rgbAt(src, format, widthPx, x - 1, rl, gl, bl);
    // Chroma co-sited with the even pixel: [1 2 1]/4 low-pass before dropping every other sample
    const int r = (rl + 2 * r0 + r1 + 2) >> 2, g = (gl + 2 * g0 + g1 + 2) >> 2, b = (bl + 2 * b0 + b1 + 2) >> 2;
    std::uint8_t* o = uyvy + 2 * x;
    o[0] = clamp8(cbOf(r, g, b));
    o[1] = clamp8(lumaOf(r0, g0, b0));
    o[2] = clamp8(crOf(r, g, b));
    o[3] = clamp8(lumaOf(r1, g1, b1));
  }
}

void uyvyToPlanar(const std::uint8_t* uyvy, int widthPx, std::uint8_t* y, std::uint8_t* cb, std::uint8_t* cr) noexcept {
  for (int i = 0; i < (widthPx + 1) / 2; ++i) {
    const std::uint8_t* p = uyvy + 4 * i;
    cb[i] = p[0];
    y[2 * i] = p[1];
    cr[i] = p[2];
    if (2 * i + 1 < widthPx) y[2 * i + 1] = p[3];  // an odd width leaves the last pair half used
  }
}

void rowToRgb(const std::uint8_t* src, PixelFormat format, int widthPx, std::uint8_t* rgb, bool bgr) noexcept {
  const int ri = bgr ? 2 : 0, bi = bgr ? 0 : 2;
  switch (format) {
    case PixelFormat::Rgb8:
      for (int x = 0; x < widthPx; ++x) {
        rgb[3 * x + ri] = src[3 * x];
        rgb[3 * x + 1] = src[3 * x + 1];
        rgb[3 * x + bi] = src[3 * x + 2];
      }
      return;
    case PixelFormat::Grey8:
      for (int x = 0; x < widthPx; ++x) rgb[3 * x] = rgb[3 * x + 1] = rgb[3 * x + 2] = src[x];
      return;
    case PixelFormat::Uyvy422:
      for (int x = 0; x < widthPx; ++x) {
        const int pair = x / 2;
        int cb = src[4 * pair], cr = src[4 * pair + 2];
        if ((x & 1) && pair + 1 < widthPx / 2) {  // odd pixel: halfway between two co-sited samples
          cb = (cb + src[4 * pair + 4] + 1) >> 1;
          cr = (cr + src[4 * pair + 6] + 1) >> 1;
        }
        const int c = 298 * (src[4 * pair + 1 + 2 * (x & 1)] - 16), d = cb - 128, e = cr - 128;
        rgb[3 * x + ri] = clamp8((c + 409 * e + 128) >> 8);
        rgb[3 * x + 1] = clamp8((c - 100 * d - 208 * e + 128) >> 8);
        rgb[3 * x + bi] = clamp8((c + 516 * d + 128) >> 8);
      }
      return;
  }
}

void averageRows(const std::uint8_t* a, const std::uint8_t* b, int count, std::uint8_t* out) noexcept {
  for (int i = 0; i < count; ++i) out[i] = static_cast<std::uint8_t>((a[i] + b[i] + 1) >> 1);
}

}  // namespace fieldcast::io
