// Stitching the channels' field images, with OpenCV.
#include "StitchedSheet.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace fieldcast::tools {
namespace {

// A field image at the frame's shape: a top or bottom field has half the rows.
cv::Mat frameShaped(const std::filesystem::path& path) {
  cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (image.empty()) throw std::runtime_error(path.string() + ": cannot read the image");
  const std::string name = path.filename().string();
  const bool field = name.find("_top.") != std::string::npos || name.find("_bottom.") != std::string::npos;
  if (field) cv::resize(image, image, cv::Size(image.cols, image.rows * 2), 0, 0, cv::INTER_LINEAR);
  return image;
}

}  // namespace

SheetWritten writeStitchedSheet(const std::vector<ChannelRun>& channels, const std::filesystem::path& path, int rows) {
  SheetWritten written;
  written.leastContrast = 255.0;
  std::vector<std::uint64_t> instants;  // field numbers every channel has an image of
  if (!channels.empty()) {
    for (const auto& [k, file] : channels.front().images) {
      bool everywhere = true;
      for (const ChannelRun& c : channels) everywhere = everywhere && c.images.count(k) != 0;
      if (everywhere) instants.push_back(k);
    }
  }
  if (instants.empty()) throw std::runtime_error("no field number has an image from every channel (sinks.images)");
  const int count = std::min<int>(rows, static_cast<int>(instants.size()));
  std::vector<cv::Mat> stacked;
  for (int r = 0; r < count; ++r) {
    // Spread through the run: the first and the last instant included
    const std::size_t i = count == 1 ? 0 : r * (instants.size() - 1) / static_cast<std::size_t>(count - 1);
    const std::uint64_t k = instants[i];
    std::vector<cv::Mat> row;
    for (const ChannelRun& c : channels) {
      cv::Mat image = frameShaped(c.images.at(k));
      cv::Mat grey;
      cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
      cv::Scalar mean, deviation;
      cv::meanStdDev(grey, mean, deviation);
      written.leastContrast = std::min(written.leastContrast, deviation[0]);
      if (!row.empty() && image.rows != row.front().rows) {
        cv::resize(image, image, cv::Size(image.cols * row.front().rows / image.rows, row.front().rows));
      }
      row.push_back(image);
    }
    cv::Mat line;
    cv::hconcat(row, line);
    char label[64];
    std::snprintf(label, sizeof label, "field %llu", static_cast<unsigned long long>(k));
    cv::putText(line, label, {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.55, {0, 0, 0}, 3, cv::LINE_AA);
    cv::putText(line, label, {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.55, {255, 255, 255}, 1, cv::LINE_AA);
    if (!stacked.empty() && line.cols != stacked.front().cols) {
      cv::resize(line, line, cv::Size(stacked.front().cols, line.rows * stacked.front().cols / line.cols));
    }
    stacked.push_back(line);
  }
  cv::Mat sheet;
  cv::vconcat(stacked, sheet);
  if (!cv::imwrite(path.string(), sheet)) throw std::runtime_error(path.string() + ": cannot write the sheet");
  written.rows = count;
  return written;
}

}  // namespace fieldcast::tools
