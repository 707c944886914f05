#pragma once
// Where a libFuzzer target may write its seed inputs: the corpus directory (the first argument that
// is not a flag) when it exists and is still empty. A corpus that already holds inputs is left
// alone.

#include <filesystem>
#include <optional>
#include <string>
#include <system_error>

namespace fieldcast::io::testdata {

inline std::optional<std::filesystem::path> emptyCorpusDirectory(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.empty() || arg[0] == '-') continue;
    std::error_code ec;
    if (std::filesystem::is_directory(arg, ec) && std::filesystem::is_empty(arg, ec)) return arg;
    return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace fieldcast::io::testdata
