#pragma once
// What the service emitted, read back the way an outside observer would: the per-field log
// (metrics.field_log: each field's number, display and emission instants on CLOCK_MONOTONIC,
// and its pose) and the fields' pixels from the Y4M file. The end-to-end latency tests find the
// first field that shows an input with these.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fieldcast::testing {

/// One line of the field log.
struct LoggedField {
  std::uint64_t number = 0;
  std::int64_t displayNs = 0;
  std::int64_t emittedNs = 0;
  double xM = 0, yM = 0, zM = 0;
  double headingDeg = 0, pitchDeg = 0, rollDeg = 0;
  bool black = false;
  bool hasHostSample = false;  ///< with a host: a sample had arrived (host_frame given)
};

/// Reads a field log (header line, then one field per line). Empty when the file is missing;
/// throws std::runtime_error on a line without its 14 columns.
inline std::vector<LoggedField> readFieldLog(const std::string& path) {
  std::vector<LoggedField> fields;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) c.push_back(cell);
    if (!line.empty() && line.back() == ',') c.emplace_back();  // an empty last column
    if (c.size() != 14) throw std::runtime_error("field log: 14 columns expected: " + line);
    LoggedField f;
    f.number = std::stoull(c[0]);
    f.displayNs = std::stoll(c[1]);
    f.emittedNs = std::stoll(c[2]);
    f.xM = std::stod(c[3]);
    f.yM = std::stod(c[4]);
    f.zM = std::stod(c[5]);
    f.headingDeg = std::stod(c[6]);
    f.pitchDeg = std::stod(c[7]);
    f.rollDeg = std::stod(c[8]);
    f.black = c[11] == "1";
    f.hasHostSample = !c[12].empty();
    fields.push_back(f);
  }
  return fields;
}

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

}  // namespace fieldcast::testing
