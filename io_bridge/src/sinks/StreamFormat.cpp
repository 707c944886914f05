#include <io_bridge/StreamFormat.h>

#include <numeric>
#include <sstream>
#include <stdexcept>

namespace fieldcast::io {

RationalRate StreamFormat::frameRate() const noexcept {
  if (scan == ScanMode::Progressive) return fieldRate;
  RationalRate r = fieldRate;
  r.denominator *= 2;
  const std::int64_t g = std::gcd(r.numerator, r.denominator);
  return RationalRate{r.numerator / g, r.denominator / g};
}

std::size_t StreamFormat::maxFieldBytes() const noexcept {
  const FieldParity largest = scan == ScanMode::Progressive ? FieldParity::Progressive : FieldParity::Top;
  return rowBytes(pixelFormat, widthPx) * static_cast<std::size_t>(fieldRows(largest));
}

bool StreamFormat::accepts(const Field& field) const noexcept {
  const bool parityFits = scan == ScanMode::Progressive ? field.parity == FieldParity::Progressive
                                                        : field.parity != FieldParity::Progressive;
  return parityFits && field.image.widthPx() == widthPx && field.image.format() == pixelFormat &&
         field.rasterHeightPx == heightPx && field.image.heightPx() == fieldRows(field.parity);
}

std::string StreamFormat::describe() const {
  std::ostringstream s;
  s << widthPx << 'x' << heightPx << ' ' << toString(pixelFormat) << ' '
    << (scan == ScanMode::Progressive
            ? "progressive"
            : (fieldOrder == FieldOrder::TopFirst ? "interlaced top-first" : "interlaced bottom-first"))
    << ' ' << fieldRate.numerator << '/' << fieldRate.denominator << " Hz, pixel aspect " << pixelAspect.numerator
    << ':' << pixelAspect.denominator;
  return s.str();
}

void StreamFormat::validate() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("stream format: " + what); };
  if (widthPx < 2 || heightPx < 2 || widthPx > 16384 || heightPx > 16384) {
    fail("raster " + std::to_string(widthPx) + "x" + std::to_string(heightPx) + " out of range 2..16384");
  }
  if (pixelFormat == PixelFormat::Uyvy422 && widthPx % 2 != 0) {
    fail("uyvy422 needs an even width, got " + std::to_string(widthPx));
  }
  if (scan == ScanMode::Interlaced && heightPx % 2 != 0) {
    fail("interlaced output needs an even height, got " + std::to_string(heightPx));
  }
  if (fieldRate.numerator <= 0 || fieldRate.denominator <= 0) fail("field rate must be positive");
  if (pixelAspect.numerator <= 0 || pixelAspect.denominator <= 0) fail("pixel aspect must be positive");
}

PixelAspect defaultPixelAspect(int widthPx, int heightPx) noexcept {
  // Rec. 601 sampling of a 4:3 picture: 525-line rasters have tall pixels (10:11), 625-line
  // rasters wide ones (12:11). These are the ratios ffmpeg and most players assume.
  const bool rec601Width = widthPx == 720 || widthPx == 704;
  if (rec601Width && (heightPx == 480 || heightPx == 486)) return {10, 11};
  if (rec601Width && heightPx == 576) return {12, 11};
  return {1, 1};
}

}  // namespace fieldcast::io
