#pragma once
// USB reconnection by hotplug: where libusb has it (LIBUSB_CAP_HAS_HOTPLUG: Linux with udev or
// netlink), a callback registered for the stick's vendor/product wakes StickInput's reconnect wait
// when the device arrives. Without it the watch is not made and StickInput's backoff poll alone
// finds the device again (it stays the fallback either way). The bus is a seam: libusb on
// hardware, a fake in tests.

#include <io_bridge/StickInput.h>
#include <io_bridge/UsbHidSource.h>

#include <fieldcast/Time.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace fieldcast::io {

/// What the reconnect wait needs from libusb's hotplug API.
class UsbHotplugBus {
 public:
  virtual ~UsbHotplugBus() = default;
  /// libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG).
  virtual bool hasHotplug() const = 0;
  /// Registers `onArrival` for arrivals of devices with these IDs (empty: any). Throws with the reason.
  virtual void watchArrivals(std::optional<std::uint16_t> vendorId, std::optional<std::uint16_t> productId,
                             std::function<void()> onArrival) = 0;
  /// Runs the pending hotplug callbacks, waiting up to `timeout` for one.
  virtual void handleEvents(Nanoseconds timeout) = 0;
};

/// libusb's hotplug in a context of its own. Throws when libusb cannot start.
std::unique_ptr<UsbHotplugBus> openLibusbHotplugBus();

/// An arrival watch for the selector's device on `bus`, or null when the bus has no hotplug (the
/// poll alone then). Throws when the callback cannot be registered.
std::unique_ptr<DeviceArrivalWatch> watchUsbArrivals(std::unique_ptr<UsbHotplugBus> bus,
                                                     const UsbDeviceSelector& selector);

}  // namespace fieldcast::io
