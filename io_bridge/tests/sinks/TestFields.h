#pragma once
// Test fields with a pattern that differs in every field, row and byte, so a swapped field, a
// shifted row or a lost packet shows.

#include <io_bridge/StreamFormat.h>

#include <fieldcast/Field.h>

#include <cstdint>

namespace fieldcast::io::testing {

/// Byte `i` of raster row `row` of field `k`.
inline std::uint8_t patternByte(std::uint64_t k, int row, int i) {
  return static_cast<std::uint8_t>((k * 37 + static_cast<std::uint64_t>(row) * 11 + static_cast<std::uint64_t>(i) * 3) &
                                   0xff);
}

/// Field k of a stream in `format`, displayed at t0 + k·T.
inline Field makeField(const StreamFormat& format, std::uint64_t k, TimePoint t0 = TimePoint{}) {
  Field field;
  field.parity = parityOfField(k, format.scan, format.fieldOrder);
  field.rasterHeightPx = format.heightPx;
  field.fieldNumber = k;
  field.displayTime = t0 + format.fieldRate.tickOffset(static_cast<std::int64_t>(k));
  field.sourceFrameNumber = k / 3;
  field.sourcePoseTime = field.displayTime - std::chrono::milliseconds(20);
  field.image = Image(format.widthPx, format.fieldRows(field.parity), format.pixelFormat);
  for (int r = 0; r < field.image.heightPx(); ++r) {
    std::uint8_t* p = field.image.row(r);
    const int raster = rasterRow(field.parity, r);
    for (std::size_t i = 0; i < field.image.strideBytes(); ++i) p[i] = patternByte(k, raster, static_cast<int>(i));
  }
  return field;
}

/// A format for tests: NTSC-like interlaced UYVY unless told otherwise.
inline StreamFormat testFormat(int width = 720, int height = 486, ScanMode scan = ScanMode::Interlaced,
                               PixelFormat pixels = PixelFormat::Uyvy422) {
  StreamFormat f;
  f.widthPx = width;
  f.heightPx = height;
  f.scan = scan;
  f.pixelFormat = pixels;
  f.fieldOrder = FieldOrder::BottomFirst;
  f.fieldRate = scan == ScanMode::Interlaced ? RationalRate{60000, 1001} : RationalRate{60000, 1001};
  f.pixelAspect = defaultPixelAspect(width, height);
  return f;
}

}  // namespace fieldcast::io::testing
