// Reading a channel's folder: the field log's columns are config/README.md, "[metrics]".
#include "ChannelRun.h"

#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace fieldcast::tools {

std::map<std::uint64_t, LoggedField> readFieldLog(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot read (the channel's metrics.field_log)");
  std::map<std::uint64_t, LoggedField> fields;
  std::string line;
  std::getline(in, line);
  if (line.rfind("field,display_ns,emitted_ns,", 0) != 0) throw std::runtime_error(path.string() + ": not a field log");
  int lineNumber = 1;
  while (std::getline(in, line)) {
    ++lineNumber;
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    if (cells.size() < 13) {
      if (in.peek() == std::char_traits<char>::eof()) break;  // the last line, cut short by a kill
      throw std::runtime_error(path.string() + ":" + std::to_string(lineNumber) + ": short line");
    }
    LoggedField f;
    f.displayNs = std::stoll(cells[1]);
    f.emittedNs = std::stoll(cells[2]);
    f.xM = std::stod(cells[3]);
    f.yM = std::stod(cells[4]);
    f.zM = std::stod(cells[5]);
    f.black = cells[11] == "1";
    if (!cells[12].empty()) f.hostFrame = std::stoll(cells[12]);
    fields[std::stoull(cells[0])] = f;
  }
  return fields;
}

ChannelRun readChannelRun(const std::string& name, const std::filesystem::path& folder) {
  ChannelRun run;
  run.name = name;
  run.fields = readFieldLog(folder / "fields.csv");
  std::ifstream summary(folder / "summary.json");
  if (!summary) throw std::runtime_error((folder / "summary.json").string() + ": cannot read");
  try {
    run.summary = nlohmann::json::parse(summary);
  } catch (const std::exception& e) {
    throw std::runtime_error((folder / "summary.json").string() + ": " + e.what());
  }
  // sinks.images names a field <prefix>_<number, 8 digits>_<parity>.png
  const std::regex imageName(R"(.*_(\d{8,})_(top|bottom|progressive)\.png)");
  if (std::filesystem::is_directory(folder / "images")) {
    for (const auto& entry : std::filesystem::directory_iterator(folder / "images")) {
      std::smatch match;
      const std::string file = entry.path().filename().string();
      if (std::regex_match(file, match, imageName)) run.images[std::stoull(match[1].str())] = entry.path();
    }
  }
  return run;
}

}  // namespace fieldcast::tools
