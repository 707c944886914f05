#pragma once
// The field warper's end of a warp: each piece of a warped row, as the warp writes it, is
// mirrored, measured for the automatic gain and converted under the gain into the output field,
// while it is still in the first-level cache. A field is written once, in its output format.

#include <prp_warp/FieldRows.h>
#include <prp_warp/PostProcess.h>

#include <fieldcast/Image.h>

#include <cstdint>
#include <vector>

namespace fieldcast::warp {

class FieldAssembly final : public FieldPieceSink {
 public:
  /// Room for rows of up to `maxWidthPx` pixels (allocates).
  explicit FieldAssembly(int maxWidthPx);

  /// Starts a field: the pieces a warp writes to rows() go into `out` (the field's rows, in the
  /// output format), mirrored by `mirror`, under the gain `gainQ16` (1/65536); with `measure`
  /// the luma of every 2nd pixel of every 2nd row of `out` (as meanLuma(out, 2) counts them) is
  /// summed for meanLuma(). `out` must be no wider than the room reserved, and even in UYVY,
  /// where each piece must also start on an even column and be an even number of pixels wide
  /// (a 4:2:2 pair shares its chroma): the warps' strips of 256 and whole rows are. RT-safe.
  void start(Image& out, Mirror mirror, std::int32_t gainQ16, bool measure) noexcept;
  /// Where a warp writes the field: `out`'s shape, in the frame's `format` (Rgb8 or Grey8).
  FieldRows rows(PixelFormat format) noexcept;

  void take(int first, int n, int r, const std::uint8_t* pixels) noexcept override;

  /// The mean luma (0..255) of the pixels measured since start(); 0 when none were.
  double meanLuma() const noexcept;

 private:
  Image* mOut = nullptr;
  PixelFormat mFormat = PixelFormat::Rgb8;  // the pieces' format (the frame's)
  Mirror mMirror = Mirror::None;
  std::int32_t mGainQ16 = 1 << 16;
  bool mMeasure = false;
  std::uint64_t mLumaSum = 0;
  std::uint64_t mLumaCount = 0;
  std::vector<std::uint8_t> mPiece;     // what the warp writes
  std::vector<std::uint8_t> mReversed;  // a piece mirrored left to right
};

}  // namespace fieldcast::warp
