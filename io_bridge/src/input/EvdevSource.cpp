#include <io_bridge/EvdevSource.h>

#include "input/SystemError.h"

#include <libevdev/libevdev.h>

#include <fcntl.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <stdexcept>
#include <utility>

namespace fieldcast::io {
namespace {

// Owns the device's file and its libevdev handle: moved, never copied (a copy assigned over a
// handle freed the libevdev and closed the file the copy went on to use).
struct Evdev {
  int fd = -1;
  libevdev* dev = nullptr;
  Evdev() = default;
  Evdev(Evdev&& other) noexcept : fd(std::exchange(other.fd, -1)), dev(std::exchange(other.dev, nullptr)) {}
  Evdev& operator=(Evdev&& other) noexcept {
    if (this != &other) {
      close();
      fd = std::exchange(other.fd, -1);
      dev = std::exchange(other.dev, nullptr);
    }
    return *this;
  }
  Evdev(const Evdev&) = delete;
  Evdev& operator=(const Evdev&) = delete;
  ~Evdev() { close(); }
  void close() noexcept {
    if (dev != nullptr) libevdev_free(dev);
    if (fd >= 0) ::close(fd);
    dev = nullptr;
    fd = -1;
  }
  int release() {
    if (dev != nullptr) libevdev_free(dev);
    dev = nullptr;
    const int f = fd;
    fd = -1;
    return f;
  }
};

// Opens `path` and attaches libevdev; returns an empty handle (fd < 0) with `why` set on failure.
Evdev openEvdev(const std::string& path, std::string& why) {
  Evdev e;
  e.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (e.fd < 0) {
    why = errnoMessage(errno);
    return e;
  }
  const int rc = libevdev_new_from_fd(e.fd, &e.dev);
  if (rc < 0) {
    why = std::string("not an evdev device: ") + errnoMessage(-rc);
    ::close(e.fd);
    e.fd = -1;
    e.dev = nullptr;
  }
  return e;
}

bool looksLikeJoystick(libevdev* dev) {
  if (libevdev_has_event_code(dev, EV_ABS, ABS_X) && libevdev_has_event_code(dev, EV_ABS, ABS_Y) &&
      !libevdev_has_event_code(dev, EV_KEY, BTN_TOUCH) && !libevdev_has_property(dev, INPUT_PROP_DIRECT)) {
    return true;
  }
  return libevdev_has_event_code(dev, EV_KEY, BTN_JOYSTICK) || libevdev_has_event_code(dev, EV_KEY, BTN_GAMEPAD);
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::vector<std::string> eventNodes() {
  std::vector<std::string> paths;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/dev/input", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("event", 0) == 0) paths.push_back(entry.path().string());
  }
  // event2 before event10
  std::sort(paths.begin(), paths.end(), [](const std::string& a, const std::string& b) {
    return a.size() != b.size() ? a.size() < b.size() : a < b;
  });
  return paths;
}

}  // namespace

std::vector<EvdevDeviceInfo> listEvdevDevices() {
  std::vector<EvdevDeviceInfo> out;
  for (const std::string& path : eventNodes()) {
    std::string why;
    Evdev e = openEvdev(path, why);
    if (e.dev == nullptr) continue;
    EvdevDeviceInfo info;
    info.path = path;
    info.name = libevdev_get_name(e.dev) != nullptr ? libevdev_get_name(e.dev) : "";
    info.vendorId = static_cast<std::uint16_t>(libevdev_get_id_vendor(e.dev));
    info.productId = static_cast<std::uint16_t>(libevdev_get_id_product(e.dev));
    info.isJoystick = looksLikeJoystick(e.dev);
    out.push_back(std::move(info));
  }
  return out;
}

// After SYN_DROPPED: the kernel's current values, by ioctl (libevdev's cache is not kept, since
// events are read raw).
class EvdevSource::StateQuery final : public EvdevStateQuery {
 public:
  StateQuery(int fd, std::vector<std::uint16_t> abs, std::vector<std::uint16_t> keys)
      : mFd(fd), mAbs(std::move(abs)), mKeys(std::move(keys)) {}
  bool currentState(std::vector<EvdevCodeValue>& out) override {
    for (const std::uint16_t code : mAbs) {
      input_absinfo info{};
      if (::ioctl(mFd, EVIOCGABS(code), &info) < 0) return false;
      out.push_back({EV_ABS, code, info.value});
    }
    std::array<unsigned char, KEY_CNT / 8 + 1> bits{};
    if (::ioctl(mFd, EVIOCGKEY(bits.size()), bits.data()) < 0) return false;
    for (const std::uint16_t code : mKeys) {
      out.push_back({EV_KEY, code, (bits[code / 8] >> (code % 8)) & 1});
    }
    return true;
  }

 private:
  int mFd;
  std::vector<std::uint16_t> mAbs;
  std::vector<std::uint16_t> mKeys;
};

EvdevSource::EvdevSource(const std::string& pathOrName) {
  std::string why;
  Evdev e;
  if (pathOrName.find('/') != std::string::npos) {
    e = openEvdev(pathOrName, why);
    if (e.dev == nullptr) throw std::runtime_error("evdev " + pathOrName + ": " + why);
    mPath = pathOrName;
  } else {
    const std::string wanted = lower(pathOrName);
    for (const std::string& path : eventNodes()) {
      Evdev candidate = openEvdev(path, why);
      if (candidate.dev == nullptr || !looksLikeJoystick(candidate.dev)) continue;
      const char* name = libevdev_get_name(candidate.dev);
      if (name != nullptr && lower(name).find(wanted) != std::string::npos) {
        e = std::move(candidate);
        mPath = path;
        break;
      }
    }
    if (e.dev == nullptr)
      throw std::runtime_error("evdev: no joystick named like \"" + pathOrName + "\" in /dev/input");
  }
  // Kernel timestamps on the one clock of the system (DESIGN.md §4).
  if (libevdev_set_clock_id(e.dev, CLOCK_MONOTONIC) != 0) {
    throw std::runtime_error("evdev " + mPath + ": EVIOCSCLOCKID(CLOCK_MONOTONIC) refused");
  }
  mDescription.name = libevdev_get_name(e.dev) != nullptr ? libevdev_get_name(e.dev) : mPath;
  mDescription.transport = InputTransport::Evdev;
  mDescription.vendorId = static_cast<std::uint16_t>(libevdev_get_id_vendor(e.dev));
  mDescription.productId = static_cast<std::uint16_t>(libevdev_get_id_product(e.dev));
  std::vector<std::uint16_t> absCodes;
  std::vector<std::uint16_t> keyCodes;
  bool hat = false;
  for (std::uint16_t code = 0; code < ABS_CNT; ++code) {
    if (!libevdev_has_event_code(e.dev, EV_ABS, code)) continue;
    absCodes.push_back(code);
    if (code == ABS_HAT0X || code == ABS_HAT0Y) {
      if (!hat) mDescription.controls.push_back({usages::kHatSwitch, ControlKind::Hat, 0, kHatCentred});
      hat = true;
      continue;
    }
    const input_absinfo* info = libevdev_get_abs_info(e.dev, code);
    mDescription.controls.push_back({usageOfAbs(code), ControlKind::Axis, info != nullptr ? info->minimum : 0,
                                     info != nullptr ? info->maximum : 0});
  }
  for (std::uint16_t code = 0; code < KEY_CNT; ++code) {
    if (!libevdev_has_event_code(e.dev, EV_KEY, code)) continue;
    keyCodes.push_back(code);
    const Usage u = usageOfKey(code);
    if (u != 0) mDescription.controls.push_back({u, ControlKind::Button, 0, 1});
  }
  if (mDescription.controls.empty()) {
    throw std::runtime_error("evdev " + mPath + " (" + mDescription.name + "): no axes or stick buttons");
  }
  mFd = e.release();
  mQuery = std::make_unique<StateQuery>(mFd, std::move(absCodes), std::move(keyCodes));
  mReader = std::make_unique<EvdevStreamReader>(mFd, mQuery.get());
  // Start from the device's present state, not from zeros: the first read() delivers it.
  mReader->decoder().queryNow(MonotonicClock::now().time_since_epoch().count(), mInitial);
}

EvdevSource::~EvdevSource() {
  mReader.reset();
  if (mFd >= 0) ::close(mFd);
}

ReadResult EvdevSource::read(std::vector<InputEvent>& out, Nanoseconds timeout) {
  if (!mInitial.empty()) {
    out.insert(out.end(), mInitial.begin(), mInitial.end());
    mInitial.clear();
    return ReadResult::Events;
  }
  return mReader->read(out, timeout);
}

InputSourceStats EvdevSource::stats() const noexcept {
  return InputSourceStats{mReader->decoder().frames(), 0, mReader->decoder().droppedBursts()};
}

}  // namespace fieldcast::io
