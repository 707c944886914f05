#include "ContactSheet.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace fieldcast::app {
namespace {

// The field as an RGB picture at display aspect: an interlaced field carries every other row,
// so it is stretched back to the raster's height.
cv::Mat fieldToRgb(const Field& field) {
  const Image& image = field.image;
  cv::Mat rgb;
  switch (image.format()) {
    case PixelFormat::Rgb8:
      rgb =
          cv::Mat(image.heightPx(), image.widthPx(), CV_8UC3, const_cast<std::uint8_t*>(image.bytes().data())).clone();
      break;
    case PixelFormat::Grey8: {
      const cv::Mat grey(image.heightPx(), image.widthPx(), CV_8UC1, const_cast<std::uint8_t*>(image.bytes().data()));
      cv::cvtColor(grey, rgb, cv::COLOR_GRAY2RGB);
      break;
    }
    case PixelFormat::Uyvy422: {
      const cv::Mat uyvy(image.heightPx(), image.widthPx(), CV_8UC2, const_cast<std::uint8_t*>(image.bytes().data()));
      cv::cvtColor(uyvy, rgb, cv::COLOR_YUV2RGB_UYVY);  // BT.601, video range
      break;
    }
  }
  return rgb;
}

}  // namespace

ContactSheet::ContactSheet(int thumbnails, int columns, int thumbWidthPx, int keepEveryNth)
    : mThumbnails(std::max(1, thumbnails)),
      mColumns(std::max(1, columns)),
      mThumbWidthPx(std::max(16, thumbWidthPx)),
      mKeepEveryNth(std::max(1, keepEveryNth)) {}

void ContactSheet::add(const Field& field) {
  if (!mHaveFirst) {
    mFirstDisplayTime = field.displayTime;
    mHaveFirst = true;
  }
  if (field.fieldNumber % static_cast<std::uint64_t>(mKeepEveryNth) != 0 || field.image.empty()) return;
  const cv::Mat rgb = fieldToRgb(field);
  const int rasterHeight = field.parity == FieldParity::Progressive ? rgb.rows : field.rasterHeightPx;
  const int thumbHeight = std::max(1, rasterHeight * mThumbWidthPx / std::max(1, rgb.cols));
  cv::Mat thumb;
  cv::resize(rgb, thumb, cv::Size(mThumbWidthPx, thumbHeight), 0, 0, cv::INTER_AREA);
  Thumbnail t;
  t.rgb.assign(thumb.data, thumb.data + thumb.total() * thumb.elemSize());
  t.heightPx = thumbHeight;
  t.fieldNumber = field.fieldNumber;
  t.secondsFromStart = toSeconds(field.displayTime - mFirstDisplayTime);
  mCandidates.push_back(std::move(t));
}

void ContactSheet::write(const std::filesystem::path& path) const {
  if (mCandidates.empty()) throw std::runtime_error(path.string() + ": no fields to put on the contact sheet");
  // Pick up to mThumbnails candidates spread evenly from the first to the last.
  const int count = std::min<int>(mThumbnails, static_cast<int>(mCandidates.size()));
  std::vector<const Thumbnail*> picked;
  for (int k = 0; k < count; ++k) {
    const std::size_t index =
        count == 1 ? 0 : static_cast<std::size_t>(k) * (mCandidates.size() - 1) / static_cast<std::size_t>(count - 1);
    picked.push_back(&mCandidates[index]);
  }
  const int rows = (count + mColumns - 1) / mColumns;
  const int cellH = mCandidates.front().heightPx;
  const int gap = 4;
  cv::Mat sheet(rows * (cellH + gap) + gap, std::min(count, mColumns) * (mThumbWidthPx + gap) + gap, CV_8UC3,
                cv::Scalar(24, 24, 24));
  for (int k = 0; k < count; ++k) {
    const Thumbnail& t = *picked[static_cast<std::size_t>(k)];
    const cv::Mat thumb(t.heightPx, mThumbWidthPx, CV_8UC3, const_cast<unsigned char*>(t.rgb.data()));
    const int x = gap + (k % mColumns) * (mThumbWidthPx + gap);
    const int y = gap + (k / mColumns) * (cellH + gap);
    cv::Mat cell = sheet(cv::Rect(x, y, mThumbWidthPx, std::min(cellH, t.heightPx)));
    thumb(cv::Rect(0, 0, mThumbWidthPx, std::min(cellH, t.heightPx))).copyTo(cell);
    char label[64];
    std::snprintf(label, sizeof label, "field %llu  t=%.2f s", static_cast<unsigned long long>(t.fieldNumber),
                  t.secondsFromStart);
    cv::putText(sheet, label, cv::Point(x + 6, y + 18), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 3);
    cv::putText(sheet, label, cv::Point(x + 6, y + 18), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(255, 255, 255), 1);
  }
  cv::Mat bgr;
  cv::cvtColor(sheet, bgr, cv::COLOR_RGB2BGR);
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  if (!cv::imwrite(path.string(), bgr)) throw std::runtime_error(path.string() + ": cannot write the contact sheet");
}

}  // namespace fieldcast::app
