#pragma once
// Input → field latency in the running service, with its real clock: `fieldcast` runs as a user
// runs it, with a stick that is a HID device behind a UNIX socket (HidSocketStick) or driven by a
// CIGI host on loopback (StepHost). A step input is made again and again — the stick thrown fully
// to one side, the host's heading stepped — and each is found in what the service emitted: the
// first field whose pose shows it (the field log) and the first whose pixels do (the Y4M video).

#include <filesystem>
#include <string>
#include <vector>

namespace fieldcast::tools {

enum class EndToEndInput {
  Stick,  ///< the stick thrown fully right or left (roll rate), read by the hidraw source's loop
  Host,   ///< the host's ownship heading stepped by 10° in one host frame
};

/// "stick" or "host".
const char* name(EndToEndInput input) noexcept;

struct EndToEndSpec {
  std::string fieldcastExe;       ///< the service to run
  std::filesystem::path workDir;  ///< its configuration, terrain cache and output (created, then removed)
  EndToEndInput input = EndToEndInput::Stick;
  int steps = 40;                     ///< step inputs made
  int widthPx = 720, heightPx = 486;  ///< output raster (interlaced at 59.94 Hz)
};

struct EndToEndResult {
  EndToEndInput input = EndToEndInput::Stick;
  int steps = 0;                   ///< made while the service ran
  std::vector<double> toPoseMs;    ///< per step found: input sent → emission of the first field whose pose shows it
  std::vector<double> toPixelsMs;  ///< … whose pixels show it
  std::string problem;             ///< why nothing was measured (empty when it ran)
};

/// Runs the service and makes the steps. Never throws: a failure is reported in `problem`.
EndToEndResult measureInputToField(const EndToEndSpec& spec);

}  // namespace fieldcast::tools
