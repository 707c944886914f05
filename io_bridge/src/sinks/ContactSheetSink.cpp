#include <io_bridge/ContactSheetSink.h>

#include "ImageWrite.h"
#include "PixelConvert.h"

#include <spdlog/spdlog.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace fieldcast::io {

ContactSheetSink::ContactSheetSink(ContactSheetOptions options) : mOptions(std::move(options)) {
  mOptions.thumbnails = std::max(1, mOptions.thumbnails);
  mOptions.columns = std::max(1, mOptions.columns);
  mOptions.thumbWidthPx = std::max(16, mOptions.thumbWidthPx);
  mOptions.keepEveryNth = std::max(1, mOptions.keepEveryNth);
  mEveryNth.store(static_cast<std::uint64_t>(mOptions.keepEveryNth), std::memory_order_relaxed);
}

void ContactSheetSink::open(const StreamFormat&) {
  if (!mOptions.path.has_parent_path()) return;
  std::error_code error;
  std::filesystem::create_directories(mOptions.path.parent_path(), error);
  if (error) throw std::runtime_error(mOptions.path.parent_path().string() + ": cannot create: " + error.message());
}

bool ContactSheetSink::wants(const Field& field) const noexcept {
  return !mHaveFirst.load(std::memory_order_relaxed) || onGrid(field);
}

bool ContactSheetSink::onGrid(const Field& field) const noexcept {
  return field.fieldNumber % mEveryNth.load(std::memory_order_relaxed) == 0;
}

SinkStatus ContactSheetSink::consume(const Field& field) {
  if (!mHaveFirst.load(std::memory_order_relaxed)) {
    mFirstDisplayTime = field.displayTime;
    mHaveFirst.store(true, std::memory_order_relaxed);
  }
  if (!onGrid(field) || field.image.empty()) {
    return SinkStatus::Ok;
  }
  const int w = field.image.widthPx(), h = field.image.heightPx();
  mRgb.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  for (int r = 0; r < h; ++r) {
    rowToRgb(field.image.row(r), field.image.format(), w, mRgb.data() + static_cast<std::size_t>(r) * w * 3);
  }
  // An interlaced field carries every other row: stretch it back to the raster's shape.
  const int rasterHeight = field.parity == FieldParity::Progressive ? h : field.rasterHeightPx;
  const int thumbHeight = std::max(1, rasterHeight * mOptions.thumbWidthPx / std::max(1, w));
  const cv::Mat rgb(h, w, CV_8UC3, mRgb.data());
  cv::Mat thumb;
  cv::resize(rgb, thumb, cv::Size(mOptions.thumbWidthPx, thumbHeight), 0, 0, cv::INTER_AREA);
  Thumbnail t;
  t.rgb.assign(thumb.data, thumb.data + thumb.total() * thumb.elemSize());
  t.heightPx = thumbHeight;
  t.fieldNumber = field.fieldNumber;
  t.secondsFromStart = toSeconds(field.displayTime - mFirstDisplayTime);
  mCandidates.push_back(std::move(t));
  if (mCandidates.size() >= static_cast<std::size_t>(kCandidatesPerThumbnail) * mOptions.thumbnails) {
    // Full: a grid twice as sparse, keeping the candidates on it (every other one)
    const std::uint64_t sparser = 2 * mEveryNth.load(std::memory_order_relaxed);
    std::erase_if(mCandidates, [sparser](const Thumbnail& c) { return c.fieldNumber % sparser != 0; });
    mEveryNth.store(sparser, std::memory_order_relaxed);
  }
  return SinkStatus::Ok;
}

void ContactSheetSink::close() {
  if (mCandidates.empty()) return;
  write();
  spdlog::info("contact sheet: {}", mOptions.path.string());
}

void ContactSheetSink::write() const {
  const std::string path = mOptions.path.string();
  if (mCandidates.empty()) throw std::runtime_error(path + ": no fields to put on the contact sheet");
  // Pick up to `thumbnails` candidates spread evenly from the first to the last.
  const int count = std::min<int>(mOptions.thumbnails, static_cast<int>(mCandidates.size()));
  const int columns = mOptions.columns, thumbW = mOptions.thumbWidthPx;
  const int rows = (count + columns - 1) / columns;
  const int cellH = mCandidates.front().heightPx;
  const int gap = 4;
  cv::Mat sheet(rows * (cellH + gap) + gap, std::min(count, columns) * (thumbW + gap) + gap, CV_8UC3,
                cv::Scalar(24, 24, 24));
  for (int k = 0; k < count; ++k) {
    const std::size_t index =
        count == 1 ? 0 : static_cast<std::size_t>(k) * (mCandidates.size() - 1) / static_cast<std::size_t>(count - 1);
    const Thumbnail& t = mCandidates[index];
    const cv::Mat thumb(t.heightPx, thumbW, CV_8UC3, const_cast<unsigned char*>(t.rgb.data()));
    const int x = gap + (k % columns) * (thumbW + gap);
    const int y = gap + (k / columns) * (cellH + gap);
    const int height = std::min(cellH, t.heightPx);
    thumb(cv::Rect(0, 0, thumbW, height)).copyTo(sheet(cv::Rect(x, y, thumbW, height)));
    char label[64];
    std::snprintf(label, sizeof label, "field %llu  t=%.2f s", static_cast<unsigned long long>(t.fieldNumber),
                  t.secondsFromStart);
    cv::putText(sheet, label, cv::Point(x + 6, y + 18), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 3);
    cv::putText(sheet, label, cv::Point(x + 6, y + 18), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(255, 255, 255), 1);
  }
  const OIIO::ImageSpec spec(sheet.cols, sheet.rows, 3, OIIO::TypeDesc::UINT8);
  writeImage(mOptions.path, spec, OIIO::TypeDesc::UINT8, sheet.data);
}

}  // namespace fieldcast::io
