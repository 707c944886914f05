#pragma once
// How one stick's raw controls become ControlState: for each of roll, pitch, yaw and throttle the
// control to read (by HID usage, first one present wins), inversion, calibration range, dead zone
// and expo; the button order; what to do when the device is lost. Profiles are TOML files in
// config/sticks/ (keys documented in config/README.md); the generic profile fits any joystick
// that reports X/Y/Rz and a throttle.

#include <io_bridge/InputEvent.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fieldcast::io {

/// The four axes a stick drives.
enum class AxisRole : std::uint8_t { Roll, Pitch, Yaw, Throttle };
/// Number of axis roles.
constexpr std::size_t kAxisRoles = 4;
/// "roll", "pitch", "yaw", "throttle".
std::string_view axisRoleName(AxisRole role) noexcept;

/// How one role is read from the device.
struct AxisBinding {
  std::vector<Usage> controls;  ///< candidates, first present on the device wins; empty: unbound
  bool invert = false;
  std::optional<std::int32_t> min;  ///< calibration; default: the device's reported range
  std::optional<std::int32_t> max;
  std::optional<std::int32_t> center;  ///< default: midpoint of min and max (roll, pitch, yaw only)
  double deadZone = 0.0;               ///< fraction of the half range (bipolar) or of the range (throttle), 0…0.5
  double expo = 0.0;                   ///< 0 linear … 1 cubic: (1−e)·x + e·x³
};

/// What the published state does when the device disappears.
enum class ThrottleOnLoss : std::uint8_t { Hold, Neutral };

/// Which ControlState buttons (1…64, after `buttonOrder`) drive the cockpit's actions; 0: none.
/// They act as the GPIO discretes of the same name do (app/src/CockpitActions.h).
struct CockpitButtons {
  int freeze = 0;   ///< each press toggles the freeze
  int reset = 0;    ///< each press returns the flight to its start
  int trigger = 0;  ///< each press is counted
};

/// A per-device mapping profile.
struct StickProfile {
  std::string name = "generic";
  std::vector<std::string> match;            ///< device-name substrings this profile is for (informative)
  std::array<AxisBinding, kAxisRoles> axes;  ///< indexed by AxisRole
  std::vector<std::uint16_t>
      buttonOrder;               ///< ControlState button n = device button buttonOrder[n−1]; empty: same numbers
  CockpitButtons cockpit;        ///< [buttons] freeze / reset / trigger
  double defaultThrottle = 0.5;  ///< throttle when no throttle control is bound or present
  double lossDecayS = 1.0;       ///< seconds for roll/pitch/yaw to decay to neutral after a loss
  ThrottleOnLoss throttleOnLoss = ThrottleOnLoss::Hold;

  const AxisBinding& axis(AxisRole r) const noexcept { return axes[static_cast<std::size_t>(r)]; }
  AxisBinding& axis(AxisRole r) noexcept { return axes[static_cast<std::size_t>(r)]; }

  /// X → roll, Y → pitch (pulled back is nose up), Rz/Rudder → yaw, Throttle/Slider/Z → throttle
  /// (inverted: most levers read their minimum fully forward), small dead zones, no expo.
  static StickProfile generic();
};

/// Parses a profile from TOML text; `origin` names it in errors. Throws std::runtime_error:
/// "config/sticks/x.toml:7: roll.dead_zone: expected a number from 0 to 0.5, got 2".
StickProfile parseStickProfile(std::string_view toml, const std::string& origin);
/// Reads and parses a profile file. Throws as parseStickProfile, or when the file cannot be read.
StickProfile loadStickProfile(const std::filesystem::path& path);

/// A control name as profiles write it: "x", "rz", "throttle", "slider", "rudder", …,
/// "usage:0x0001:0x0030" or "abs:0x28" (an evdev ABS code). Returns 0 when unknown.
Usage parseControlName(std::string_view name) noexcept;

}  // namespace fieldcast::io
