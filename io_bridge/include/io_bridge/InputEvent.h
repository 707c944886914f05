#pragma once
// The one vocabulary every input source speaks: a control is named by its HID usage (page:id),
// whatever the transport (evdev codes are translated to the usages the kernel mapped them from),
// and a source delivers value changes grouped into frames that end with a Sync carrying the
// frame's timestamp. Recording, replay and the stick mapper work on this and nothing else.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace fieldcast::io {

/// A HID usage: page in the high 16 bits, usage id in the low 16 bits.
using Usage = std::uint32_t;

/// Builds a usage from its page and id. RT-safe.
constexpr Usage makeUsage(std::uint16_t page, std::uint16_t id) noexcept { return (Usage{page} << 16) | id; }
/// The usage page of `u`. RT-safe.
constexpr std::uint16_t usagePage(Usage u) noexcept { return static_cast<std::uint16_t>(u >> 16); }
/// The usage id of `u`. RT-safe.
constexpr std::uint16_t usageId(Usage u) noexcept { return static_cast<std::uint16_t>(u & 0xFFFFu); }

/// Usage pages and usages the stick path cares about (HID Usage Tables 1.4).
namespace usages {
constexpr std::uint16_t kGenericDesktopPage = 0x01;
constexpr std::uint16_t kSimulationPage = 0x02;
constexpr std::uint16_t kButtonPage = 0x09;
constexpr std::uint16_t kConsumerPage = 0x0C;
/// Page for evdev ABS codes that have no HID usage (id = ABS code). Vendor range, ours.
constexpr std::uint16_t kEvdevAbsPage = 0xFFE0;
constexpr Usage kX = makeUsage(kGenericDesktopPage, 0x30);
constexpr Usage kY = makeUsage(kGenericDesktopPage, 0x31);
constexpr Usage kZ = makeUsage(kGenericDesktopPage, 0x32);
constexpr Usage kRx = makeUsage(kGenericDesktopPage, 0x33);
constexpr Usage kRy = makeUsage(kGenericDesktopPage, 0x34);
constexpr Usage kRz = makeUsage(kGenericDesktopPage, 0x35);
constexpr Usage kSlider = makeUsage(kGenericDesktopPage, 0x36);
constexpr Usage kDial = makeUsage(kGenericDesktopPage, 0x37);
constexpr Usage kWheel = makeUsage(kGenericDesktopPage, 0x38);
constexpr Usage kHatSwitch = makeUsage(kGenericDesktopPage, 0x39);
constexpr Usage kRudder = makeUsage(kSimulationPage, 0xBA);
constexpr Usage kThrottle = makeUsage(kSimulationPage, 0xBB);
constexpr Usage kAccelerator = makeUsage(kSimulationPage, 0xC4);
constexpr Usage kBrake = makeUsage(kSimulationPage, 0xC5);
constexpr Usage kSteering = makeUsage(kSimulationPage, 0xC8);
/// Button n (1-based) of the Button page.
constexpr Usage button(std::uint16_t n) noexcept { return makeUsage(kButtonPage, n); }
}  // namespace usages

/// Hat switch values as every source reports them: 0 = up, clockwise in 45° steps, 8 = centred.
constexpr std::int32_t kHatCentred = 8;

/// What an event says.
enum class InputEventType : std::uint8_t {
  Value,        ///< control `usage` now has `value`
  Sync,         ///< the end of a frame of values; `tNs` is the frame's time
  DeviceLost,   ///< the device went away at `tNs`
  DeviceFound,  ///< the device (re)appeared at `tNs`
};

/// One input event. Times are CLOCK_MONOTONIC nanoseconds (kernel stamps where the kernel gives one).
struct InputEvent {
  std::int64_t tNs = 0;
  Usage usage = 0;
  std::int32_t value = 0;
  InputEventType type = InputEventType::Value;

  friend bool operator==(const InputEvent&, const InputEvent&) = default;
};

/// The kind of control behind a usage, which decides how it is mapped.
enum class ControlKind : std::uint8_t { Axis, Button, Hat };

/// One control a device offers, with its raw range.
struct ControlInfo {
  Usage usage = 0;
  ControlKind kind = ControlKind::Axis;
  std::int32_t min = 0;  ///< smallest raw value (logical minimum / absinfo minimum)
  std::int32_t max = 0;  ///< largest raw value

  friend bool operator==(const ControlInfo&, const ControlInfo&) = default;
};

/// Which transport a device was read through.
enum class InputTransport : std::uint8_t { Evdev, Hidraw, Usb, Replay, Fake };

/// A device as a source describes it: identity plus the controls it reports.
struct DeviceDescription {
  std::string name;
  InputTransport transport = InputTransport::Fake;
  std::uint16_t vendorId = 0;
  std::uint16_t productId = 0;
  std::vector<ControlInfo> controls;

  /// The control with `usage`, or nullptr.
  const ControlInfo* find(Usage usage) const noexcept;
  friend bool operator==(const DeviceDescription&, const DeviceDescription&) = default;
};

/// Classifies a usage: Button page → Button, hat switch → Hat, anything else → Axis.
ControlKind kindOfUsage(Usage usage) noexcept;
/// Short readable name of a usage ("X", "Rz", "Throttle", "Button 3", "0xff00:0x21").
std::string usageName(Usage usage);
/// Name of a transport ("evdev", "hidraw", "usb", "replay", "fake").
std::string_view transportName(InputTransport t) noexcept;

}  // namespace fieldcast::io
