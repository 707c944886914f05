#pragma once
// What one channel of a rig left in its folder: its per-field record (fields.csv, the service's
// metrics.field_log), its run summary (summary.json) and the field images it wrote
// (images/*.png, sinks.images).

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace fieldcast::tools {

/// One line of a field log: what the rig report compares.
struct LoggedField {
  std::int64_t displayNs = 0;
  std::int64_t emittedNs = 0;
  double xM = 0, yM = 0, zM = 0;  ///< the eye's position (the channels of a rig share it)
  bool black = false;
  std::int64_t hostFrame = -1;  ///< the host sample the pose was made from; −1: none
};

/// Reads a field log (the service's metrics.field_log CSV). Throws std::runtime_error naming the
/// file and line when it cannot be read or a line is malformed; a last line cut short (a channel
/// killed while writing) is skipped.
std::map<std::uint64_t, LoggedField> readFieldLog(const std::filesystem::path& path);

struct ChannelRun {
  std::string name;
  std::map<std::uint64_t, LoggedField> fields;  ///< by field number
  nlohmann::json summary;
  std::map<std::uint64_t, std::filesystem::path> images;  ///< by field number
};

/// Reads `folder`/fields.csv, summary.json and images/. Throws std::runtime_error naming the file
/// that is missing or malformed.
ChannelRun readChannelRun(const std::string& name, const std::filesystem::path& folder);

}  // namespace fieldcast::tools
