#pragma once
// A video field: what prp_warp produces and the io_bridge sinks emit, one every field period.

#include <fieldcast/Image.h>
#include <fieldcast/Time.h>

#include <cstdint>

namespace fieldcast {

/// Which rows of the output raster a field carries.
enum class FieldParity : std::uint8_t {
  Top,          ///< rows 0, 2, 4, … (the "top" or "even" field)
  Bottom,       ///< rows 1, 3, 5, …
  Progressive,  ///< every row: progressive output has one field per frame period
};

/// Order in which the two fields of an interlaced frame are shown.
enum class FieldOrder : std::uint8_t {
  TopFirst,
  BottomFirst,
};

/// Scan mode of an output stream.
enum class ScanMode : std::uint8_t {
  Progressive,
  Interlaced,
};

/// Rows a field of `parity` carries out of a raster `rasterHeightPx` rows high.
constexpr int fieldRowCount(FieldParity parity, int rasterHeightPx) noexcept {
  switch (parity) {
    case FieldParity::Top: return (rasterHeightPx + 1) / 2;
    case FieldParity::Bottom: return rasterHeightPx / 2;
    case FieldParity::Progressive: return rasterHeightPx;
  }
  return 0;
}

/// Raster row of row `fieldRow` of a field of `parity`. RT-safe.
constexpr int rasterRow(FieldParity parity, int fieldRow) noexcept {
  switch (parity) {
    case FieldParity::Top: return 2 * fieldRow;
    case FieldParity::Bottom: return 2 * fieldRow + 1;
    case FieldParity::Progressive: return fieldRow;
  }
  return fieldRow;
}

/// Parity of field number `k` of a stream. RT-safe.
constexpr FieldParity parityOfField(std::uint64_t k, ScanMode scan, FieldOrder order) noexcept {
  if (scan == ScanMode::Progressive) return FieldParity::Progressive;
  const bool first = (k % 2) == 0;
  const bool top = (order == FieldOrder::TopFirst) == first;
  return top ? FieldParity::Top : FieldParity::Bottom;
}

/// One output field. `image` holds only this field's rows (all rows for Progressive), already
/// scaled to the output raster and converted to the output pixel format.
struct Field {
  Image image;
  FieldParity parity = FieldParity::Progressive;
  int rasterHeightPx = 0;               ///< rows of the full output raster the field belongs to
  std::uint64_t fieldNumber = 0;        ///< k, counted from the start of the stream
  TimePoint displayTime{};              ///< t_k: when the field is shown
  std::uint64_t sourceFrameNumber = 0;  ///< the frame it was warped from
  TimePoint sourcePoseTime{};           ///< that frame's pose time (frame age = displayTime − this)
  /// Output pixels whose source fell outside the frame (outside its footprint, for a rolled one)
  std::uint32_t marginViolations = 0;
  /// The first field after the field clock moved onto another frame lock: its number does not
  /// follow the previous field's, though no field was lost between them.
  bool renumbered = false;
};

}  // namespace fieldcast
