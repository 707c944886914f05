#pragma once
// Decoding of the kernel's evdev stream (struct input_event, Documentation/input/event-codes.rst):
// events are buffered until SYN_REPORT closes the frame, which is then delivered with the
// kernel's timestamp. After SYN_DROPPED (the kernel's buffer overflowed) everything up to and
// including the next SYN_REPORT is discarded and the device's current state is queried instead,
// so no press or release is lost for good. Codes are translated to the HID usages the kernel's
// hid-input mapped them from, so profiles work the same for evdev, hidraw and raw USB.

#include <io_bridge/InputEvent.h>
#include <io_bridge/InputSource.h>

#include <fieldcast/Time.h>

#include <linux/input.h>

#include <array>
#include <bitset>
#include <cstdint>
#include <vector>

namespace fieldcast::io {

/// The current value of one evdev code (type EV_ABS or EV_KEY).
struct EvdevCodeValue {
  std::uint16_t type = 0;
  std::uint16_t code = 0;
  std::int32_t value = 0;
};

/// Answers "what is the state of the device now?" after SYN_DROPPED. A real device answers with
/// the EVIOCGABS/EVIOCGKEY ioctls; tests answer with a scripted state.
class EvdevStateQuery {
 public:
  virtual ~EvdevStateQuery() = default;
  /// Appends the current value of every ABS and KEY code the device supports. False on failure.
  virtual bool currentState(std::vector<EvdevCodeValue>& out) = 0;
};

/// The HID usage an evdev ABS code was mapped from (inverse of hid-input.c); ABS_HAT0X/Y give
/// the hat switch; unmapped codes get usages::kEvdevAbsPage. RT-safe.
Usage usageOfAbs(std::uint16_t code) noexcept;
/// The Button usage of a joystick/gamepad key code (BTN_TRIGGER.., BTN_SOUTH.., BTN_TRIGGER_HAPPY..),
/// or 0 for keys that are not stick buttons. RT-safe.
Usage usageOfKey(std::uint16_t code) noexcept;
/// Hat direction (0..7 clockwise from up, or kHatCentred) from evdev's HAT0X/HAT0Y (-1, 0, 1). RT-safe.
std::int32_t hatFromAxes(std::int32_t x, std::int32_t y) noexcept;

/// Turns a stream of input_event into InputEvent frames. One thread.
class EvdevDecoder {
 public:
  /// `resync` may be null (then a drop is only counted; the next frames catch up).
  explicit EvdevDecoder(EvdevStateQuery* resync) noexcept : mResync(resync) {}

  /// Feeds one kernel event; appends a complete frame to `out` on SYN_REPORT.
  void feed(const input_event& ev, std::vector<InputEvent>& out);

  /// Queries the device's state now and appends it as a frame at `tNs` (used when a device is
  /// opened, so the mapper starts from where the stick is).
  void queryNow(std::int64_t tNs, std::vector<InputEvent>& out);

  /// Frames lost to SYN_DROPPED so far (each recovered by a resync).
  std::uint64_t droppedBursts() const noexcept { return mDropped; }
  /// Frames delivered so far.
  std::uint64_t frames() const noexcept { return mFrames; }

 private:
  void apply(std::uint16_t type, std::uint16_t code, std::int32_t value, std::int64_t tNs,
             std::vector<InputEvent>& out);
  void resync(std::int64_t tNs, std::vector<InputEvent>& out, bool everything);
  void endFrame(std::int64_t tNs, std::size_t before, bool forceHat, std::vector<InputEvent>& out);

  EvdevStateQuery* mResync;
  bool mDropping = false;
  std::vector<input_event> mPending;
  std::vector<EvdevCodeValue> mQueried;
  std::array<std::int32_t, ABS_CNT> mAbs{};
  std::bitset<KEY_CNT> mKeys;
  std::int32_t mHat = kHatCentred;  // last hat direction emitted
  bool mHasHat = false;             // the device reports HAT0X/HAT0Y (known after a state query)
  std::uint64_t mDropped = 0;
  std::uint64_t mFrames = 0;
};

/// Reads struct input_event from a file descriptor — an evdev device or, in tests, a pipe — and
/// decodes it. Does not own the descriptor.
class EvdevStreamReader {
 public:
  EvdevStreamReader(int fd, EvdevStateQuery* resync) noexcept : mFd(fd), mDecoder(resync) {}

  /// Waits up to `timeout` (poll), reads what is there, appends complete frames. A read that
  /// returns 0 (pipe closed) is End; ENODEV (device unplugged) is Lost.
  ReadResult read(std::vector<InputEvent>& out, Nanoseconds timeout);

  const EvdevDecoder& decoder() const noexcept { return mDecoder; }
  EvdevDecoder& decoder() noexcept { return mDecoder; }

 private:
  int mFd;
  EvdevDecoder mDecoder;
  std::array<std::uint8_t, 64 * sizeof(input_event)> mBuffer{};
  std::size_t mHave = 0;  // bytes of an incomplete event kept from the previous read
};

}  // namespace fieldcast::io
