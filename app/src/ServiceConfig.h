#pragma once
// The service configuration: what config/fieldcast.toml says, validated. Every key is
// documented in config/README.md. Errors name the file, the key and what was expected.

#include <fieldcast/Field.h>
#include <fieldcast/Image.h>
#include <fieldcast/Time.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace fieldcast::app {

/// A configuration error; what() reads "file:line: key: expected …, got …".
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The [output] table: the video the service emits.
struct OutputConfig {
  RationalRate fieldRate{60000, 1001};  ///< fields per second (59.94 by default)
  ScanMode scan = ScanMode::Interlaced;
  FieldOrder fieldOrder = FieldOrder::BottomFirst;  ///< NTSC 486-line video is bottom field first
  int widthPx = 720;
  int heightPx = 486;
  PixelFormat format = PixelFormat::Uyvy422;
};

/// The whole configuration.
struct ServiceConfig {
  std::string sourcePath;  ///< file it was read from
  OutputConfig output;
};

/// Reads and validates a configuration file, then applies `overrides` ("table.key=value", as
/// given to --set). Throws ConfigError on the first problem.
ServiceConfig loadServiceConfig(const std::string& path, const std::vector<std::string>& overrides = {});

}  // namespace fieldcast::app
