#pragma once
// The format of the field stream the sinks receive: raster size, pixel format, scan, field order,
// field rate and pixel aspect. Every sink is opened with one StreamFormat and every Field it is
// given must match it.

#include <fieldcast/Field.h>
#include <fieldcast/Image.h>
#include <fieldcast/Time.h>

#include <cstdint>
#include <string>

namespace fieldcast::io {

/// Pixel aspect ratio (width of a pixel over its height), as a reduced fraction.
struct PixelAspect {
  int numerator = 1;
  int denominator = 1;
  friend bool operator==(const PixelAspect&, const PixelAspect&) = default;
};

/// The output stream as every sink sees it.
struct StreamFormat {
  int widthPx = 720;                                ///< raster width (even for UYVY)
  int heightPx = 486;                               ///< raster height, all rows of a frame
  PixelFormat pixelFormat = PixelFormat::Uyvy422;   ///< format of Field::image
  ScanMode scan = ScanMode::Interlaced;             ///< interlaced: two fields per frame
  FieldOrder fieldOrder = FieldOrder::BottomFirst;  ///< which field of a frame is shown first
  RationalRate fieldRate{60000, 1001};              ///< fields per second (frames when progressive)
  PixelAspect pixelAspect{10, 11};                  ///< see defaultPixelAspect()

  /// Frames per second: the field rate halved when interlaced (59.94 fields → 30000/1001 frames).
  RationalRate frameRate() const noexcept;
  /// Rows of a field of `parity` in this raster.
  int fieldRows(FieldParity parity) const noexcept { return fieldRowCount(parity, heightPx); }
  /// Bytes of the largest field (all rows when progressive, the top field when interlaced).
  std::size_t maxFieldBytes() const noexcept;
  /// Parity of the first field of each frame (Progressive when progressive).
  FieldParity firstParity() const noexcept { return parityOfField(0, scan, fieldOrder); }
  /// Whether a field belongs to this stream: width, format, raster height, parity and row count.
  /// RT-safe.
  bool accepts(const Field& field) const noexcept;
  /// "720x486 uyvy422 interlaced bottom-first 59.94 Hz", for logs.
  std::string describe() const;
  /// Throws std::invalid_argument naming what is wrong (odd UYVY width, odd interlaced height…).
  void validate() const;
};

/// The pixel aspect a viewer expects for a raster shown at 4:3 when it is a Rec. 601 size
/// (720×480/486: 10:11, 720×576: 12:11, 704 wide likewise), square pixels otherwise.
PixelAspect defaultPixelAspect(int widthPx, int heightPx) noexcept;

}  // namespace fieldcast::io
