#pragma once
// Stick → field latency in the running service, with its real clock: `fieldcast` flies a stick
// that is a HID device behind a UNIX socket (HidSocketStick); the stick is thrown again and again,
// and each throw is found in what the service emitted — the first field whose pose shows it
// (the field log) and the first whose pixels do (the Y4M video).

#include <filesystem>
#include <string>
#include <vector>

namespace fieldcast::tools {

struct EndToEndSpec {
  std::string fieldcastExe;           ///< the service to run
  std::filesystem::path workDir;      ///< its configuration, terrain cache and output (created)
  int throws = 40;                    ///< stick throws, alternately right and left
  int widthPx = 720, heightPx = 486;  ///< output raster (interlaced at 59.94 Hz)
};

struct EndToEndResult {
  int throws = 0;                ///< made while the service ran
  std::vector<double> toPoseMs;  ///< per throw found: report write → emission of the first field whose pose shows it
  std::vector<double> toPixelsMs;  ///< … whose pixels show it
  std::string problem;             ///< why nothing was measured (empty when it ran)
};

/// Runs the service and throws the stick. Never throws: a failure is reported in `problem`.
EndToEndResult measureStickToField(const EndToEndSpec& spec);

}  // namespace fieldcast::tools
