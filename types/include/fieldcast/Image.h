#pragma once
// An 8-bit image buffer: the pixels of frames and fields. Rows are contiguous and tightly
// packed (stride = width × bytes per pixel), top row first.

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace fieldcast {

/// Pixel layouts of frames and fields.
enum class PixelFormat : std::uint8_t {
  Grey8,    ///< one byte of luma per pixel
  Rgb8,     ///< three bytes R, G, B per pixel (sRGB-encoded)
  Uyvy422,  ///< Cb Y0 Cr Y1 per pair of pixels (BT.601, video range); width must be even
};

/// Bytes one row of `widthPx` pixels occupies in `format`.
constexpr std::size_t rowBytes(PixelFormat format, int widthPx) noexcept {
  switch (format) {
    case PixelFormat::Grey8: return static_cast<std::size_t>(widthPx);
    case PixelFormat::Rgb8: return static_cast<std::size_t>(widthPx) * 3;
    case PixelFormat::Uyvy422: return static_cast<std::size_t>(widthPx) * 2;
  }
  return 0;
}

/// Name of a pixel format, as written in configuration files and logs.
constexpr const char* toString(PixelFormat format) noexcept {
  switch (format) {
    case PixelFormat::Grey8: return "grey8";
    case PixelFormat::Rgb8: return "rgb8";
    case PixelFormat::Uyvy422: return "uyvy422";
  }
  return "?";
}

/// A width × height 8-bit image in one of the PixelFormats. Allocates only in the constructor
/// and resize(); everything else is RT-safe.
class Image {
 public:
  Image() = default;
  /// Allocates a zeroed image. Throws std::invalid_argument for negative sizes or an odd
  /// width in UYVY.
  Image(int widthPx, int heightPx, PixelFormat format) { resize(widthPx, heightPx, format); }

  /// Reshapes the image; keeps the allocation when it is large enough.
  void resize(int widthPx, int heightPx, PixelFormat format) {
    if (widthPx < 0 || heightPx < 0) {
      throw std::invalid_argument("Image: negative size " + std::to_string(widthPx) + "x" + std::to_string(heightPx));
    }
    if (format == PixelFormat::Uyvy422 && widthPx % 2 != 0) {
      throw std::invalid_argument("Image: UYVY 4:2:2 needs an even width, got " + std::to_string(widthPx));
    }
    mWidthPx = widthPx;
    mHeightPx = heightPx;
    mFormat = format;
    mBytes.assign(rowBytes(format, widthPx) * static_cast<std::size_t>(heightPx), 0);
  }

  int widthPx() const noexcept { return mWidthPx; }
  int heightPx() const noexcept { return mHeightPx; }
  PixelFormat format() const noexcept { return mFormat; }
  bool empty() const noexcept { return mBytes.empty(); }
  /// Same width, height and pixel format as `other` (the pixels aside).
  bool sameShape(const Image& other) const noexcept {
    return mWidthPx == other.mWidthPx && mHeightPx == other.mHeightPx && mFormat == other.mFormat;
  }
  /// Bytes per row (tightly packed).
  std::size_t strideBytes() const noexcept { return rowBytes(mFormat, mWidthPx); }

  /// Row `y` (0 = top). RT-safe; `y` must be in range.
  std::uint8_t* row(int y) noexcept { return mBytes.data() + static_cast<std::size_t>(y) * strideBytes(); }
  const std::uint8_t* row(int y) const noexcept { return mBytes.data() + static_cast<std::size_t>(y) * strideBytes(); }
  std::span<std::uint8_t> bytes() noexcept { return mBytes; }
  std::span<const std::uint8_t> bytes() const noexcept { return mBytes; }

  friend bool operator==(const Image&, const Image&) = default;

 private:
  int mWidthPx = 0;
  int mHeightPx = 0;
  PixelFormat mFormat = PixelFormat::Rgb8;
  std::vector<std::uint8_t> mBytes;
};

}  // namespace fieldcast
