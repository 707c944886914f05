// A field written once: each warped piece mirrored, measured for the AGC and converted in place.
#include <prp_warp/FieldAssembly.h>

#include "LumaSum.h"
#include "PixelConversion.h"

#include <algorithm>
#include <cassert>

namespace fieldcast::warp {

FieldAssembly::FieldAssembly(int maxWidthPx)
    : mPiece(rowBytes(PixelFormat::Rgb8, std::max(maxWidthPx, 0))),
      mReversed(rowBytes(PixelFormat::Rgb8, std::max(maxWidthPx, 0))) {}

void FieldAssembly::start(Image& out, Mirror mirror, std::int32_t gainQ16, bool measure) noexcept {
  mOut = &out;
  mMirror = mirror;
  mGainQ16 = gainQ16;
  mMeasure = measure;
  mLumaSum = 0;
  mLumaCount = 0;
}

FieldRows FieldAssembly::rows(PixelFormat format) noexcept {
  mFormat = format;
  return {mOut->widthPx(), mOut->heightPx(), format, mPiece.data(), *this};
}

void FieldAssembly::take(int first, int n, int r, const std::uint8_t* pixels) noexcept {
  const int channels = mFormat == PixelFormat::Rgb8 ? 3 : 1;
  assert(mOut->format() != PixelFormat::Uyvy422 || (first % 2 == 0 && n % 2 == 0));
  // Where the piece lands in the output: mirrored, row r shows the field's last row but r, and
  // the piece's columns run right to left from the mirror image of its first
  const int row = mirrorsRows(mMirror) ? mOut->heightPx() - 1 - r : r;
  int column = first;
  if (mirrorsColumns(mMirror)) {
    column = mOut->widthPx() - first - n;
    for (int i = 0; i < n; ++i) {
      std::copy_n(pixels + (n - 1 - i) * channels, channels, mReversed.data() + i * channels);
    }
    pixels = mReversed.data();
  }
  // meanLuma(out, 2)'s pixels: the even columns of the even rows, counted as it counts them
  if (mMeasure && row % 2 == 0) {
    const int skip = column % 2;  // the piece's first pixel on an even column
    if (n > skip) {
      const std::uint8_t* from = pixels + skip * channels;
      mLumaSum +=
          channels == 3 ? luma::rgbLumaSumRowLanes(from, n - skip, true) : luma::lumaSumRowScalar(from, 1, n - skip, 2);
      mLumaCount += static_cast<std::uint64_t>((n - skip + 1) / 2);
    }
  }
  conversion::convertRow(pixels, mFormat, n, mOut->format(), mGainQ16, true,
                         mOut->row(row) + rowBytes(mOut->format(), column));
}

double FieldAssembly::meanLuma() const noexcept {
  return mLumaCount ? static_cast<double>(mLumaSum) / static_cast<double>(mLumaCount) : 0.0;
}

}  // namespace fieldcast::warp
