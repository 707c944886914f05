#include <io_bridge/InputSources.h>

#include <io_bridge/EvdevSource.h>
#include <io_bridge/HidReportDescriptor.h>
#include <io_bridge/HidrawSource.h>
#include <io_bridge/InputRecording.h>
#include <io_bridge/UsbHidSource.h>
#include <io_bridge/UsbHotplug.h>

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace fieldcast::io {

namespace {

// "hidsocket:PATH:descriptor=F" (see InputSources.h).
struct HidSocketSpec {
  std::string path;
  std::vector<std::uint8_t> descriptor;
};

HidSocketSpec parseHidSocketSpec(const std::string& spec) {
  const std::string rest = spec.substr(10);
  const auto d = rest.find(":descriptor=");
  if (d == std::string::npos || d == 0) {
    throw std::runtime_error("input source \"" + spec + "\": expected hidsocket:<socket path>:descriptor=<file>");
  }
  HidSocketSpec s{rest.substr(0, d), readHidDescriptorFile(rest.substr(d + 12))};
  (void)parseHidReportDescriptor(s.descriptor);  // refuse a bad file now, with its reason
  sockaddr_un address{};
  if (s.path.size() >= sizeof address.sun_path) {
    throw std::runtime_error("input source \"" + spec + "\": the socket path is longer than " +
                             std::to_string(sizeof address.sun_path - 1) + " bytes");
  }
  return s;
}

/// Connects to the device server's socket; throws naming the path and the reason (the stick
/// input retries with backoff, as for an unplugged device).
int connectHidSocket(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::runtime_error(path + ": socket: " + std::strerror(errno));
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path, path.data(), path.size());
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    const int error = errno;
    ::close(fd);
    throw std::runtime_error(path + ": cannot connect to the HID socket: " + std::strerror(error));
  }
  return fd;
}

struct UsbSpec {
  UsbDeviceSelector selector;
  std::vector<std::uint8_t> descriptor;
};

// "usb:…" (see InputSources.h).
UsbSpec parseUsbSpec(const std::string& spec) {
  std::string rest = spec.substr(4);
  std::vector<std::uint8_t> descriptor;
  if (const auto d = rest.find(":descriptor="); d != std::string::npos) {
    descriptor = readHidDescriptorFile(rest.substr(d + 12));
    (void)parseHidReportDescriptor(descriptor);  // refuse a bad file now, with its reason
    rest.resize(d);
  }
  bool detach = false;
  if (rest.size() > 7 && rest.substr(rest.size() - 7) == ":detach") {
    detach = true;
    rest.resize(rest.size() - 7);
  }
  UsbDeviceSelector sel;
  if (rest.rfind("class:", 0) == 0) {
    // A panel that is not bound to usbhid: the first device with an interface of that class.
    const std::string cls = rest.substr(6);
    std::size_t used = 0;
    unsigned long v = 256;
    try {
      v = std::stoul(cls, &used, 0);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != cls.size() || v > 255)
      throw std::runtime_error("input source \"" + spec + "\": expected usb:class:N with N 0-255");
    sel.interfaceClass = static_cast<std::uint8_t>(v);
  } else {
    sel = parseUsbSelector(rest);
  }
  sel.detachKernelDriver = detach;
  return UsbSpec{sel, descriptor};
}

}  // namespace

bool isReplaySpec(const std::string& spec) noexcept { return spec.rfind("replay:", 0) == 0; }

StickInput::SourceFactory makeSourceFactory(const std::string& spec, Clock& clock) {
  if (spec.empty()) throw std::runtime_error("input source: empty name");
  auto after = [&](std::size_t n) { return spec.substr(n); };
  if (spec.rfind("hidraw:", 0) == 0) {
    const std::string path = after(7);
    return [path] { return std::make_unique<HidrawSource>(path); };
  }
  if (spec.rfind("hidsocket:", 0) == 0) {
    const HidSocketSpec hid = parseHidSocketSpec(spec);
    return [hid] { return std::make_unique<HidrawSource>(connectHidSocket(hid.path), hid.descriptor, hid.path); };
  }
  if (spec.rfind("usb:", 0) == 0) {
    const UsbSpec usb = parseUsbSpec(spec);
    return [sel = usb.selector, descriptor = usb.descriptor] {
      return std::make_unique<UsbHidSource>(openLibusbTransport(sel), descriptor);
    };
  }
  if (isReplaySpec(spec)) {
    std::string path = after(7);
    ReplayPacing pacing = ReplayPacing::AsFastAsPossible;
    if (path.size() > 9 && path.substr(path.size() - 9) == ":realtime") {
      pacing = ReplayPacing::RealTime;
      path.resize(path.size() - 9);
    }
    (void)readInputRecording(path);  // fail now, with file:line, if it is not a recording
    return [path, pacing, &clock] { return std::make_unique<ReplaySource>(path, pacing, clock); };
  }
  const std::string evdev = spec.rfind("evdev:", 0) == 0 ? after(6) : spec;
  return [evdev] { return std::make_unique<EvdevSource>(evdev); };
}

std::shared_ptr<DeviceArrivalWatch> makeArrivalWatch(const std::string& spec) {
  if (spec.rfind("usb:", 0) != 0) return nullptr;
  return watchUsbArrivals(openLibusbHotplugBus(), parseUsbSpec(spec).selector);
}

}  // namespace fieldcast::io
