#pragma once
// A joystick read through the kernel's evdev interface (/dev/input/event*). libevdev describes
// the device (name, IDs, axis ranges, supported codes) and sets its timestamps to
// CLOCK_MONOTONIC (EVIOCSCLOCKID); events are read raw and decoded by EvdevDecoder, the same code
// the pipe-fed tests exercise; after SYN_DROPPED the state is re-read with EVIOCGABS/EVIOCGKEY.

#include <io_bridge/EvdevDecoder.h>
#include <io_bridge/InputSource.h>

#include <memory>
#include <string>
#include <vector>

namespace fieldcast::io {

/// One evdev device found on the system.
struct EvdevDeviceInfo {
  std::string path;  ///< /dev/input/eventN
  std::string name;
  std::uint16_t vendorId = 0;
  std::uint16_t productId = 0;
  bool isJoystick = false;  ///< reports absolute X/Y or joystick/gamepad buttons
};

/// Lists /dev/input/event* that can be opened (sorted by path). Not RT-safe.
std::vector<EvdevDeviceInfo> listEvdevDevices();

/// An evdev joystick. Construction opens it; throws std::runtime_error naming the device and the
/// reason (not found, permission, not a joystick).
class EvdevSource final : public InputSource {
 public:
  /// `pathOrName`: a device path, or a case-insensitive substring of the device name (the first
  /// joystick whose name matches is opened).
  explicit EvdevSource(const std::string& pathOrName);
  ~EvdevSource() override;
  EvdevSource(const EvdevSource&) = delete;
  EvdevSource& operator=(const EvdevSource&) = delete;

  const DeviceDescription& description() const noexcept override { return mDescription; }
  ReadResult read(std::vector<InputEvent>& out, Nanoseconds timeout) override;
  InputSourceStats stats() const noexcept override;
  /// The path that was opened.
  const std::string& path() const noexcept { return mPath; }

 private:
  class StateQuery;
  std::string mPath;
  int mFd = -1;
  DeviceDescription mDescription;
  std::unique_ptr<StateQuery> mQuery;
  std::unique_ptr<EvdevStreamReader> mReader;
  std::vector<InputEvent> mInitial;  // the state at open, delivered by the first read()
};

}  // namespace fieldcast::io
