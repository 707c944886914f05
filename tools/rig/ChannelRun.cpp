// Reading a channel's folder: the field log's columns are config/README.md, "[metrics]".
#include "ChannelRun.h"

#include <fstream>
#include <regex>
#include <stdexcept>
#include <vector>

namespace fieldcast::tools {

std::map<std::uint64_t, LoggedField> byNumber(const std::vector<LoggedField>& fields) {
  std::map<std::uint64_t, LoggedField> numbered;
  for (const LoggedField& f : fields) numbered[f.number] = f;
  return numbered;
}

ChannelRun readChannelRun(const std::string& name, const std::filesystem::path& folder) {
  ChannelRun run;
  run.name = name;
  const std::filesystem::path log = folder / "fields.csv";
  if (!std::filesystem::is_regular_file(log))
    throw std::runtime_error(log.string() + ": cannot read (the channel's metrics.field_log)");
  run.fields = byNumber(readFieldLog(log.string()));
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
