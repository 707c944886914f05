#include <io_bridge/InputEvent.h>

#include <array>
#include <cstdio>

namespace fieldcast::io {

const ControlInfo* DeviceDescription::find(Usage usage) const noexcept {
  for (const ControlInfo& c : controls) {
    if (c.usage == usage) return &c;
  }
  return nullptr;
}

ControlKind kindOfUsage(Usage usage) noexcept {
  if (usagePage(usage) == usages::kButtonPage) return ControlKind::Button;
  if (usage == usages::kHatSwitch) return ControlKind::Hat;
  return ControlKind::Axis;
}

std::string usageName(Usage usage) {
  using namespace usages;
  static constexpr std::array<const char*, 10> kDesktop{"X",  "Y",      "Z",    "Rx",    "Ry",
                                                        "Rz", "Slider", "Dial", "Wheel", "Hat switch"};
  const std::uint16_t page = usagePage(usage);
  const std::uint16_t id = usageId(usage);
  if (page == kGenericDesktopPage && id >= 0x30 && id <= 0x39) return kDesktop[id - 0x30];
  if (page == kButtonPage) return "Button " + std::to_string(id);
  switch (usage) {
    case kRudder: return "Rudder";
    case kThrottle: return "Throttle";
    case kAccelerator: return "Accelerator";
    case kBrake: return "Brake";
    case kSteering: return "Steering";
    default: break;
  }
  std::array<char, 24> buf{};
  if (page == kEvdevAbsPage) {
    std::snprintf(buf.data(), buf.size(), "ABS 0x%02x", id);
  } else {
    std::snprintf(buf.data(), buf.size(), "0x%04x:0x%04x", page, id);
  }
  return buf.data();
}

std::string_view transportName(InputTransport t) noexcept {
  switch (t) {
    case InputTransport::Evdev: return "evdev";
    case InputTransport::Hidraw: return "hidraw";
    case InputTransport::Usb: return "usb";
    case InputTransport::Replay: return "replay";
    case InputTransport::Fake: return "fake";
  }
  return "?";
}

}  // namespace fieldcast::io
