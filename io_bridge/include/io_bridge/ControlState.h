#pragma once
// What the pilot's hands say, normalised: the value the input thread publishes and the field
// thread (through the flight model) reads. The axes use the sign conventions and ranges of
// motion::FlightControls, so `FlightControls{s.roll, s.pitch, s.yaw, s.throttle}` is the whole mapping.

#include <io_bridge/InputEvent.h>

#include <fieldcast/Time.h>

#include <cstdint>

namespace fieldcast::io {

/// Where the published state comes from.
enum class InputHealth : std::uint8_t {
  NoDevice,  ///< never connected: neutral controls
  Live,      ///< the device is connected and reporting
  Holding,   ///< the device was lost: the last state decays to neutral (ControlState::lostAt)
};

/// The normalised control state. Trivially copyable (it travels through a SeqLock).
struct ControlState {
  TimePoint time{};                ///< timestamp of the input frame this state reflects (kernel time where known)
  double roll = 0.0;               ///< −1 … 1, right wing down positive (stick right)
  double pitch = 0.0;              ///< −1 … 1, nose up positive (stick pulled back)
  double yaw = 0.0;                ///< −1 … 1, nose right positive (right rudder / twist right)
  double throttle = 0.5;           ///< 0 … 1
  std::uint64_t buttons = 0;       ///< bit n−1 set while button n is pressed (buttons 1…64)
  std::int32_t hat = kHatCentred;  ///< 0…7 clockwise from up, or kHatCentred
  InputHealth health = InputHealth::NoDevice;
  TimePoint lostAt{};  ///< when the device was lost (health == Holding)

  /// True while button n (1-based) is pressed. RT-safe.
  constexpr bool button(int n) const noexcept { return n >= 1 && n <= 64 && ((buttons >> (n - 1)) & 1u) != 0; }
  friend bool operator==(const ControlState&, const ControlState&) = default;
};

}  // namespace fieldcast::io
