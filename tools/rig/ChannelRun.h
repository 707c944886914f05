#pragma once
// What one channel of a rig left in its folder: its per-field record (fields.csv, the service's
// metrics.field_log), its run summary (summary.json) and the field images it wrote
// (images/*.png, sinks.images).

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <tools/FieldLogReader.h>

#include <nlohmann/json.hpp>

namespace fieldcast::tools {

/// A field log's fields by their number.
std::map<std::uint64_t, LoggedField> byNumber(const std::vector<LoggedField>& fields);

struct ChannelRun {
  std::string name;
  std::map<std::uint64_t, LoggedField> fields;  ///< by field number
  nlohmann::json summary;
  std::map<std::uint64_t, std::filesystem::path> images;  ///< by field number
  int fieldCpu = -1;  ///< the CPU its field thread was pinned to (threads.field_thread_cpu); −1: not pinned
};

/// Reads `folder`/fields.csv, summary.json and images/. Throws std::runtime_error naming the file
/// that is missing or malformed.
ChannelRun readChannelRun(const std::string& name, const std::filesystem::path& folder);

}  // namespace fieldcast::tools
