#pragma once
// One way to name an input source, shared by the service ([input] stick) and fieldcast-stick:
//   /dev/input/event5 or a name substring   evdev (libevdev)
//   evdev:<path or name>                     the same, explicit
//   hidraw:/dev/hidraw3                      hidraw, our HID parser
//   usb:044f:0409[:detach]                   raw USB HID through libusb (detach usbhid if asked)
//   usb:class:255[:detach][:descriptor=F]    the first device with an interface of that class (panels
//                                            not bound to usbhid); F gives the report descriptor
//                                            when the interface has no HID descriptor
//   hidsocket:<path>:descriptor=F            a HID device bridged over a UNIX SOCK_SEQPACKET socket at
//                                            path: one input report per message, report descriptor
//                                            from F (a device server, a bridge from another bus, a
//                                            test rig); read by the hidraw source's own loop
//   replay:<file>[:realtime]                 a recording played back

#include <io_bridge/InputSource.h>
#include <io_bridge/StickInput.h>

#include <fieldcast/Time.h>

#include <memory>
#include <string>

namespace fieldcast::io {

/// A factory that opens the source `spec` names (each call opens it anew, for reconnection).
/// Throws std::runtime_error at once when the spec itself is malformed; the factory throws when
/// the device is not there.
StickInput::SourceFactory makeSourceFactory(const std::string& spec, Clock& clock);

/// For usb: sources where libusb has hotplug, a watch that wakes the reconnect wait when the
/// device arrives; null otherwise (evdev, hidraw, replays, no hotplug: the backoff poll alone).
/// Throws std::runtime_error when libusb cannot start or the callback cannot be registered.
std::shared_ptr<DeviceArrivalWatch> makeArrivalWatch(const std::string& spec);

/// True when `spec` names a recording (a replay does not reconnect).
bool isReplaySpec(const std::string& spec) noexcept;

}  // namespace fieldcast::io
