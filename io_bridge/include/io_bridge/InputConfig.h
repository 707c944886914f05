#pragma once
// The [input] section of the service configuration (keys in config/README.md): the control
// stick, its profile and recording, the external field-sync line and the cockpit discretes.

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
  std::string freeze;             ///< GPIO line of the freeze discrete (frozen while on); empty: none
  std::string reset;              ///< GPIO line of the reset discrete (each press); empty: none
  std::string trigger;            ///< GPIO line of the trigger discrete (each press counted); empty: none
};

/// Reads [input] (stick, profile, record, sync, freeze, reset, trigger). Throws ConfigError.
InputConfig readInputConfig(ConfigReader& table);

}  // namespace fieldcast::io
