// Image files through OpenImageIO (ImageOutput::create picks the writer from the extension).

#include <io_bridge/ImageFileSink.h>

#include "ImageWrite.h"
#include "PixelConvert.h"

#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace fieldcast::io {

namespace {

// sRGB decoding (IEC 61966-2-1) for EXR, which holds linear light; a table of the 256 codes.
float srgbToLinear(std::uint8_t v) noexcept {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      t[static_cast<std::size_t>(i)] =
          static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table[v];
}

const char* parityName(FieldParity p) noexcept {
  switch (p) {
    case FieldParity::Top: return "top";
    case FieldParity::Bottom: return "bottom";
    case FieldParity::Progressive: return "progressive";
  }
  return "?";
}

}  // namespace

ImageFileSink::ImageFileSink(ImageFileSinkOptions options) : mOptions(std::move(options)) {}
ImageFileSink::~ImageFileSink() = default;

void ImageFileSink::open(const StreamFormat& format) {
  if (!std::filesystem::is_directory(mOptions.directory)) {
    throw std::runtime_error("sinks.images.directory: " + mOptions.directory.string() + " is not a folder");
  }
  if (mOptions.everyNth < 0) throw std::invalid_argument("sinks.images.every_nth must be 0 or more");
  mFormat = format;
  const auto pixels = static_cast<std::size_t>(format.widthPx) * static_cast<std::size_t>(format.heightPx);
  mRgb.assign(pixels * 3, 0);
  if (mOptions.format == ImageFileFormat::Exr) mLinear.assign(pixels * 3, 0.0f);
}

std::string ImageFileSink::fileName(const Field& field) const {
  char number[32];
  std::snprintf(number, sizeof number, "%08llu", static_cast<unsigned long long>(field.fieldNumber));
  return mOptions.prefix + "_" + number + "_" + parityName(field.parity) +
         (mOptions.format == ImageFileFormat::Png ? ".png" : ".exr");
}

bool ImageFileSink::due(const Field& field) const noexcept {
  return mOptions.everyNth > 0 && field.fieldNumber % static_cast<std::uint64_t>(mOptions.everyNth) == 0;
}

bool ImageFileSink::wants(const Field& field) const noexcept {
  return due(field) || mSnapshot.load(std::memory_order_relaxed);
}

SinkStatus ImageFileSink::consume(const Field& field) {
  // A field written on the grid also answers a snapshot asked for: cleared either way
  const bool snapshot = mSnapshot.exchange(false, std::memory_order_relaxed);
  if (!due(field) && !snapshot) return SinkStatus::Ok;

  const int w = field.image.widthPx(), h = field.image.heightPx();
  for (int r = 0; r < h; ++r) {
    rowToRgb(field.image.row(r), field.image.format(), w, mRgb.data() + static_cast<std::size_t>(r) * w * 3);
  }
  OIIO::ImageSpec spec(w, h, 3, mOptions.format == ImageFileFormat::Png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::HALF);
  // A field row stands for two raster rows: halve the pixel aspect so the picture keeps its shape
  const float rasterAspect =
      static_cast<float>(mFormat.pixelAspect.numerator) / static_cast<float>(mFormat.pixelAspect.denominator);
  spec.attribute("PixelAspectRatio", field.parity == FieldParity::Progressive ? rasterAspect : rasterAspect / 2.0f);
  spec.attribute("fieldcast:fieldNumber", std::to_string(field.fieldNumber));
  spec.attribute("fieldcast:parity", parityName(field.parity));
  spec.attribute("fieldcast:displayTimeNs", std::to_string(field.displayTime.time_since_epoch().count()));
  spec.attribute("fieldcast:sourceFrameNumber", std::to_string(field.sourceFrameNumber));
  spec.attribute("fieldcast:marginViolations", static_cast<int>(field.marginViolations));
  // zlib level 1: a 720×243 field in a few ms instead of ~20 at the default level 6, for ~15 %
  // larger files; snapshots are for looking at, not archiving.
  spec.attribute("png:compressionLevel", 1);
  const std::filesystem::path path = mOptions.directory / fileName(field);
  try {
    if (mOptions.format == ImageFileFormat::Png) {
      writeImage(path, spec, OIIO::TypeDesc::UINT8, mRgb.data());
    } else {
      spec.attribute("oiio:ColorSpace", "Linear");
      const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3;
      for (std::size_t i = 0; i < n; ++i) mLinear[i] = srgbToLinear(mRgb[i]);
      writeImage(path, spec, OIIO::TypeDesc::FLOAT, mLinear.data());
    }
  } catch (const std::exception& e) {
    mEndReason = e.what();  // a full disk or a removed folder ends this sink, not the service
    return SinkStatus::Ended;
  }
  ++mWritten;
  mLastPath = path;
  return SinkStatus::Ok;
}

void ImageFileSink::close() {}

void writeFrameImage(const Frame& frame, const std::filesystem::path& path) {
  const int w = frame.image.widthPx(), h = frame.image.heightPx();
  const auto pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::vector<std::uint8_t> rgb(pixels * 3);
  for (int r = 0; r < h; ++r)
    rowToRgb(frame.image.row(r), frame.image.format(), w, rgb.data() + static_cast<std::size_t>(r) * w * 3);
  const bool exr = path.extension() == ".exr";
  const bool withRange = exr && frame.hasRange() && frame.rangeM.size() == pixels;
  OIIO::ImageSpec spec(w, h, withRange ? 4 : 3, exr ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8);
  spec.attribute("fieldcast:frameNumber", std::to_string(frame.frameNumber));
  spec.attribute("fieldcast:poseTimeNs", std::to_string(frame.poseTime.time_since_epoch().count()));
  spec.attribute("fieldcast:marginPx", std::to_string(frame.margin.x) + " " + std::to_string(frame.margin.y));
  if (!exr) {
    writeImage(path, spec, OIIO::TypeDesc::UINT8, rgb.data());
    return;
  }
  spec.attribute("oiio:ColorSpace", "Linear");
  const int channels = withRange ? 4 : 3;
  std::vector<float> values(pixels * static_cast<std::size_t>(channels));
  for (std::size_t i = 0; i < pixels; ++i) {
    for (int c = 0; c < 3; ++c) values[i * channels + c] = srgbToLinear(rgb[i * 3 + c]);
    if (withRange) values[i * channels + 3] = frame.rangeM[i];
  }
  if (withRange) {
    // Range in metres needs full float precision; colour is fine as half.
    spec.channelnames = {"R", "G", "B", "Z"};
    spec.channelformats = {OIIO::TypeDesc::HALF, OIIO::TypeDesc::HALF, OIIO::TypeDesc::HALF, OIIO::TypeDesc::FLOAT};
    spec.z_channel = 3;
  }
  writeImage(path, spec, OIIO::TypeDesc::FLOAT, values.data());
}

}  // namespace fieldcast::io
