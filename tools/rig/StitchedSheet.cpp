// Stitching the channels' field images, with OpenCV.
#include "StitchedSheet.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
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
  // Driven by a host, a channel shows its own start-up pose until the host's first sample: the
  // sheet shows the flight, from the first field every channel made from the host's samples.
  bool hostDriven = false;
  for (const ChannelRun& c : channels) {
    for (const auto& [k, field] : c.fields) hostDriven = hostDriven || field.hostFrame >= 0;
  }
  const auto flying = [&](const ChannelRun& c, std::uint64_t k) {
    const auto field = c.fields.find(k);
    return !hostDriven || (field != c.fields.end() && field->second.hostFrame >= 0);
  };
  std::vector<std::uint64_t> instants;  // field numbers every channel has an image of
  if (!channels.empty()) {
    for (const auto& [k, file] : channels.front().images) {
      bool everywhere = true;
      for (const ChannelRun& c : channels) everywhere = everywhere && c.images.count(k) != 0 && flying(c, k);
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
    const double scale = std::max(0.5, line.cols / 2400.0);  // readable on a sheet shown shrunk
    const cv::Point at{10, static_cast<int>(30 * scale)};
    cv::putText(line, label, at, cv::FONT_HERSHEY_SIMPLEX, scale, {0, 0, 0}, static_cast<int>(4 * scale), cv::LINE_AA);
    cv::putText(line, label, at, cv::FONT_HERSHEY_SIMPLEX, scale, {255, 255, 255},
                static_cast<int>(std::ceil(1.5 * scale)), cv::LINE_AA);
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
