#pragma once
// The service's per-field log (metrics.field_log, columns in config/README.md "[metrics]") read
// back the way an outside observer would: by the latency bench (tools/latency) and the rig's
// report (tools/rig).

#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fieldcast::tools {

/// One line of the field log.
struct LoggedField {
  std::uint64_t number = 0;
  std::int64_t displayNs = 0;
  std::int64_t emittedNs = 0;
  double xM = 0, yM = 0, zM = 0;
  double headingDeg = 0, pitchDeg = 0, rollDeg = 0;
  bool black = false;
  std::uint32_t marginPx = 0;   ///< pixels sampled outside what the frame rendered
  bool hasHostSample = false;   ///< with a host: a sample had arrived (host_frame given)
  std::int64_t hostFrame = -1;  ///< ... its host frame number; −1: none
};

/// Reads a field log (header line, then one field per line). Empty when the file is missing;
/// a last line still being written (no newline yet) is left for the next read; throws
/// std::runtime_error on a complete line without its 15 columns.
inline std::vector<LoggedField> readFieldLog(const std::string& path) {
  std::vector<LoggedField> fields;
  std::ifstream file(path);
  std::stringstream whole;
  whole << file.rdbuf();
  std::string text = whole.str();
  text.resize(text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1);
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) c.push_back(cell);
    if (!line.empty() && line.back() == ',') c.emplace_back();  // an empty last column
    if (c.size() != 15) throw std::runtime_error("field log: 15 columns expected: " + line);
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
    f.marginPx = static_cast<std::uint32_t>(std::stoul(c[12]));
    f.hasHostSample = !c[13].empty();
    if (f.hasHostSample) f.hostFrame = std::stoll(c[13]);
    fields.push_back(f);
  }
  return fields;
}

}  // namespace fieldcast::tools
