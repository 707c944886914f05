#pragma once
// What the service emitted, read back the way an outside observer would: the per-field log
// (metrics.field_log: each field's number, display and emission instants on CLOCK_MONOTONIC,
// and its pose; tools/FieldLogReader.h) and the fields' pixels from the Y4M file, and what the
// pixels say about roll.
// The end-to-end latency measurements find the first field that shows an input with these.

#include <tools/FieldLogReader.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fieldcast::tools {

/// The luma of every field of an interlaced 4:2:0 Y4M file of `width` × `height`, in field
/// order (bottom field first, as the service writes NTSC: field 2n is frame n's odd rows, field
/// 2n + 1 its even rows). Each is width × height/2 bytes.
inline std::vector<std::string> y4mLumaFields(const std::string& path, int width, int height) {
  std::vector<std::string> fields;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::getline(in, line);  // stream header
  const std::size_t luma = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::string frame(luma, '\0');
  while (std::getline(in, line)) {  // "FRAME"
    if (!in.read(frame.data(), static_cast<std::streamsize>(luma))) break;
    in.ignore(static_cast<std::streamsize>(luma / 2));  // chroma
    for (int parity : {1, 0}) {
      std::string field;
      for (int y = parity; y < height; y += 2) field.append(frame, static_cast<std::size_t>(y) * width, width);
      fields.push_back(std::move(field));
    }
  }
  return fields;
}

/// Mean absolute difference of two same-sized luma images, in grey levels.
inline double meanAbsDifference(const std::string& a, const std::string& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    sum += std::abs(static_cast<unsigned char>(a[i]) - static_cast<unsigned char>(b[i]));
  }
  return a.empty() ? 0.0 : sum / static_cast<double>(a.size());
}

/// How far (in rows, sub-row) the picture in columns [fromX, toX) moved down from field `a` to
/// field `b` (luma, `width` wide): the shift of the strip's mean-luma row profile that matches
/// best, within ±maxShift rows.
inline double verticalShiftRows(const std::string& a, const std::string& b, int width, int fromX, int toX,
                                int maxShift = 24) {
  const int rows = static_cast<int>(a.size()) / width;
  auto profile = [&](const std::string& image) {
    std::vector<double> p(static_cast<std::size_t>(rows), 0.0);
    for (int y = 0; y < rows; ++y) {
      double sum = 0.0;
      for (int x = fromX; x < toX; ++x)
        sum += static_cast<unsigned char>(image[static_cast<std::size_t>(y) * width + x]);
      p[static_cast<std::size_t>(y)] = sum / (toX - fromX);
    }
    return p;
  };
  const std::vector<double> pa = profile(a), pb = profile(b);
  auto cost = [&](int s) {
    double sum = 0.0;
    int n = 0;
    for (int y = maxShift; y < rows - maxShift; ++y) {
      const double d = pa[static_cast<std::size_t>(y)] - pb[static_cast<std::size_t>(y + s)];
      sum += d * d;
      ++n;
    }
    return n > 0 ? sum / n : 0.0;
  };
  int best = 0;
  for (int s = -maxShift; s <= maxShift; ++s)
    if (cost(s) < cost(best)) best = s;
  if (best == -maxShift || best == maxShift) return best;
  // A parabola through the best shift and its neighbours gives the sub-row part
  const double cm = cost(best - 1), c0 = cost(best), cp = cost(best + 1);
  const double curvature = cm - 2.0 * c0 + cp;
  return best + (curvature > 0.0 ? 0.5 * (cm - cp) / curvature : 0.0);
}

/// Roll seen in the pictures: the left quarter's downward shift minus the right quarter's, in
/// rows, from field `a` to field `b`. A roll to the right moves the left side up and the right
/// side down; a turn or forward flight moves both sides alike.
inline double rollSignalRows(const std::string& a, const std::string& b, int width) {
  return verticalShiftRows(a, b, width, 0, width / 4) - verticalShiftRows(a, b, width, width - width / 4, width);
}

}  // namespace fieldcast::tools
