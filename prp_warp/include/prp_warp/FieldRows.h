#pragma once
// Where a warp writes a field's rows: in place into an image, or a piece of a row at a time
// through a small buffer to a consumer. The field warper takes the pieces (mirrors, measures and
// converts each as it comes), so a field is written once, in its output format, and the warped
// field is never stored whole.

#include <fieldcast/Image.h>

#include <cstdint>

namespace fieldcast::warp {

/// Takes the pieces of a field as a warp writes them.
class FieldPieceSink {
 public:
  virtual ~FieldPieceSink() = default;
  /// `n` pixels of field row `r` from column `first`, in the field's working format (the
  /// frame's). The bytes are valid during the call only. A sink may ask more of the pieces
  /// (FieldAssembly: for UYVY, even starts and widths). RT-safe.
  virtual void take(int first, int n, int r, const std::uint8_t* pixels) noexcept = 0;
};

/// The destination of a field: a view, cheap to copy, like std::span. A warp writes each piece of
/// a row (any run of columns, a whole row included) at begin(first, r), then calls
/// end(first, n, r). Pieces are written once and never read back.
class FieldRows {
 public:
  /// Rows written in place into `image`, whose shape and format are the field's. Implicit, as
  /// std::span from a container: an Image is the plain destination.
  FieldRows(Image& image) noexcept  // NOLINT(google-explicit-constructor)
      : mImage(&image), mWidthPx(image.widthPx()), mHeightPx(image.heightPx()), mFormat(image.format()) {}
  /// Rows of `widthPx` × `heightPx` in `format`, each piece written into `piece` (room for a
  /// whole row) and handed to `sink`.
  FieldRows(int widthPx, int heightPx, PixelFormat format, std::uint8_t* piece, FieldPieceSink& sink) noexcept
      : mWidthPx(widthPx), mHeightPx(heightPx), mFormat(format), mPiece(piece), mSink(&sink) {}

  int widthPx() const noexcept { return mWidthPx; }
  int heightPx() const noexcept { return mHeightPx; }
  PixelFormat format() const noexcept { return mFormat; }

  /// Where the piece of row `r` from column `first` is to be written.
  std::uint8_t* begin(int first, int r) noexcept { return mImage ? mImage->row(r) + rowBytes(mFormat, first) : mPiece; }
  /// The piece of `n` pixels begun at (first, r) is written.
  void end(int first, int n, int r) noexcept {
    if (mSink) mSink->take(first, n, r, mPiece);
  }

 private:
  Image* mImage = nullptr;
  int mWidthPx = 0;
  int mHeightPx = 0;
  PixelFormat mFormat = PixelFormat::Rgb8;
  std::uint8_t* mPiece = nullptr;
  FieldPieceSink* mSink = nullptr;
};

}  // namespace fieldcast::warp
