#pragma once
// The [input] section of the service configuration (keys in config/README.md): the control
// stick, its profile and recording, and the external field-sync line.

#include <fieldcast/ConfigReader.h>

#include <filesystem>
#include <string>

namespace fieldcast::io {

/// What [input] sets.
struct InputConfig {
  std::string stick;              ///< evdev path or name match, hidraw:, usb:, replay: (InputSources.h); empty: none
  std::filesystem::path profile;  ///< stick profile (config/sticks/*.toml); empty: generic
  std::filesystem::path record;   ///< record the input to this file; empty: no recording
  std::string sync;               ///< GPIO line of the external field sync ("gpiochip0:17"); empty: none
};

/// Reads [input] (stick, profile, record, sync). Throws ConfigError.
InputConfig readInputConfig(ConfigReader& table);

}  // namespace fieldcast::io
