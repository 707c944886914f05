#pragma once
// Applies a StickProfile to one device's event stream and keeps the resulting ControlState.

#include <io_bridge/ControlState.h>
#include <io_bridge/InputEvent.h>
#include <io_bridge/StickProfile.h>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace fieldcast::io {

/// A resolved calibration for one axis role.
struct AxisCalibration {
  std::int32_t min = 0;
  std::int32_t max = 0;
  std::int32_t center = 0;
  bool invert = false;
  double deadZone = 0.0;
  double expo = 0.0;
};

/// Raw value → −1…1 about the centre, with dead zone and expo (roll, pitch, yaw). RT-safe.
double shapeBipolar(std::int32_t raw, const AxisCalibration& c) noexcept;
/// Raw value → 0…1 over the range, with dead bands at both ends (throttle). RT-safe.
double shapeUnipolar(std::int32_t raw, const AxisCalibration& c) noexcept;

/// Maps one device's events to a ControlState. One thread.
class StickMapper {
 public:
  /// Resolves the profile against the device's controls. Not RT-safe.
  StickMapper(const DeviceDescription& device, const StickProfile& profile);

  /// Applies one event. Returns true when it closed a frame (a Sync): state() is then the new
  /// ControlState. Controls not reported yet read as neutral. RT-safe.
  bool apply(const InputEvent& e) noexcept;

  /// The state after the last Sync. RT-safe.
  const ControlState& state() const noexcept { return mState; }

  /// One line per role naming the control used and its calibration (for logs and the tool).
  std::string describeBindings() const;

 private:
  struct Bound {
    int control = -1;  // index into mRaw, -1: unbound
    AxisCalibration cal;
  };
  int indexOf(Usage usage) const noexcept;
  double axisValue(AxisRole role) const noexcept;

  DeviceDescription mDevice;
  StickProfile mProfile;
  std::array<Bound, kAxisRoles> mBound;
  std::vector<std::pair<Usage, int>> mIndex;  // usage → control index, sorted
  std::vector<std::int32_t> mRaw;
  std::vector<bool> mSeen;
  std::vector<std::int8_t> mButtonBit;  // per control: ControlState bit, or -1
  std::uint64_t mButtons = 0;
  std::int32_t mHat = kHatCentred;
  ControlState mState;
};

}  // namespace fieldcast::io
