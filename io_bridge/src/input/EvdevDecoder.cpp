// evdev stream decoding; SYN_DROPPED handling as Documentation/input/event-codes.rst prescribes
// ("ignore all events up to and including the next SYN_REPORT and query the device's state").
#include <io_bridge/EvdevDecoder.h>

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace fieldcast::io {

Usage usageOfAbs(std::uint16_t code) noexcept {
  using namespace usages;
  switch (code) {
    case ABS_X: return kX;
    case ABS_Y: return kY;
    case ABS_Z: return kZ;
    case ABS_RX: return kRx;
    case ABS_RY: return kRy;
    case ABS_RZ: return kRz;
    case ABS_THROTTLE: return kThrottle;  // also where hid-input puts a GD Slider
    case ABS_RUDDER: return kRudder;      // also where hid-input puts a GD Dial
    case ABS_WHEEL: return kSteering;
    case ABS_GAS: return kAccelerator;
    case ABS_BRAKE: return kBrake;
    case ABS_HAT0X:
    case ABS_HAT0Y: return kHatSwitch;
    default: return makeUsage(kEvdevAbsPage, code);
  }
}

Usage usageOfKey(std::uint16_t code) noexcept {
  // hid-input.c: joystick buttons 1..16 → BTN_JOYSTICK.., gamepad buttons 1..16 → BTN_GAMEPAD..,
  // buttons 17.. → BTN_TRIGGER_HAPPY.. (both applications).
  if (code >= BTN_JOYSTICK && code < BTN_JOYSTICK + 16)
    return usages::button(static_cast<std::uint16_t>(code - BTN_JOYSTICK + 1));
  if (code >= BTN_GAMEPAD && code < BTN_GAMEPAD + 16)
    return usages::button(static_cast<std::uint16_t>(code - BTN_GAMEPAD + 1));
  if (code >= BTN_TRIGGER_HAPPY && code <= BTN_TRIGGER_HAPPY40) {
    return usages::button(static_cast<std::uint16_t>(code - BTN_TRIGGER_HAPPY + 17));
  }
  return 0;
}

std::int32_t hatFromAxes(std::int32_t x, std::int32_t y) noexcept {
  x = std::clamp(x, -1, 1);
  y = std::clamp(y, -1, 1);
  // Indexed [y + 1][x + 1]; up is y = -1.
  static constexpr std::int32_t kTable[3][3] = {{7, 0, 1}, {6, kHatCentred, 2}, {5, 4, 3}};
  return kTable[y + 1][x + 1];
}

namespace {
std::int64_t timeOf(const input_event& ev) noexcept {
  return std::int64_t{ev.input_event_sec} * 1'000'000'000 + std::int64_t{ev.input_event_usec} * 1'000;
}
}  // namespace

void EvdevDecoder::apply(std::uint16_t type, std::uint16_t code, std::int32_t value, std::int64_t tNs,
                         std::vector<InputEvent>& out) {
  if (type == EV_ABS && code < ABS_CNT) {
    mAbs[code] = value;
    if (code == ABS_HAT0X || code == ABS_HAT0Y) return;  // one hat event per frame, in endFrame()
    out.push_back(InputEvent{tNs, usageOfAbs(code), value, InputEventType::Value});
  } else if (type == EV_KEY && code < KEY_CNT) {
    const Usage u = usageOfKey(code);
    mKeys[code] = value != 0;
    if (u != 0 && value != 2)
      out.push_back(InputEvent{tNs, u, value != 0 ? 1 : 0, InputEventType::Value});  // 2 = autorepeat
  }
}

void EvdevDecoder::resync(std::int64_t tNs, std::vector<InputEvent>& out, bool everything) {
  mQueried.clear();
  if (mResync == nullptr || !mResync->currentState(mQueried)) return;
  for (const EvdevCodeValue& s : mQueried) {
    if (s.type == EV_ABS && (s.code == ABS_HAT0X || s.code == ABS_HAT0Y)) mHasHat = true;
    if (s.type == EV_ABS && s.code < ABS_CNT) {
      if (everything || mAbs[s.code] != s.value) apply(EV_ABS, s.code, s.value, tNs, out);
    } else if (s.type == EV_KEY && s.code < KEY_CNT) {
      if (everything || mKeys[s.code] != (s.value != 0)) apply(EV_KEY, s.code, s.value, tNs, out);
    }
  }
}

void EvdevDecoder::endFrame(std::int64_t tNs, std::size_t before, bool forceHat, std::vector<InputEvent>& out) {
  const std::int32_t hat = hatFromAxes(mAbs[ABS_HAT0X], mAbs[ABS_HAT0Y]);
  if (hat != mHat || forceHat) out.push_back(InputEvent{tNs, usages::kHatSwitch, hat, InputEventType::Value});
  mHat = hat;
  if (out.size() != before) {
    out.push_back(InputEvent{tNs, 0, 0, InputEventType::Sync});
    ++mFrames;
  }
}

void EvdevDecoder::queryNow(std::int64_t tNs, std::vector<InputEvent>& out) {
  const std::size_t before = out.size();
  resync(tNs, out, true);
  endFrame(tNs, before, mHasHat, out);
}

void EvdevDecoder::feed(const input_event& ev, std::vector<InputEvent>& out) {
  if (ev.type == EV_SYN && ev.code == SYN_DROPPED) {
    mPending.clear();
    mDropping = true;
    ++mDropped;
    return;
  }
  if (ev.type != EV_SYN || ev.code != SYN_REPORT) {
    if (!mDropping) mPending.push_back(ev);
    return;
  }
  // SYN_REPORT: the frame is complete.
  const std::int64_t tNs = timeOf(ev);
  const std::size_t before = out.size();
  if (mDropping) {
    mDropping = false;
    resync(tNs, out, false);
  } else {
    for (const input_event& e : mPending) apply(e.type, e.code, e.value, tNs, out);
  }
  mPending.clear();
  endFrame(tNs, before, false, out);
}

ReadResult EvdevStreamReader::read(std::vector<InputEvent>& out, Nanoseconds timeout) {
  pollfd p{mFd, POLLIN, 0};
  const auto ms = static_cast<int>(std::max<std::int64_t>(0, (timeout.count() + 999'999) / 1'000'000));
  const int ready = ::poll(&p, 1, ms);
  if (ready < 0) return errno == EINTR ? ReadResult::Timeout : ReadResult::Lost;
  if (ready == 0) return ReadResult::Timeout;
  const std::size_t before = out.size();
  const ssize_t n = ::read(mFd, mBuffer.data() + mHave, mBuffer.size() - mHave);
  if (n == 0) return ReadResult::End;
  if (n < 0) {
    if (errno == EAGAIN || errno == EINTR) return ReadResult::Timeout;
    return ReadResult::Lost;  // ENODEV: unplugged
  }
  mHave += static_cast<std::size_t>(n);
  const std::size_t whole = mHave / sizeof(input_event);
  for (std::size_t i = 0; i < whole; ++i) {
    input_event ev{};
    std::memcpy(&ev, mBuffer.data() + i * sizeof(input_event), sizeof(input_event));
    mDecoder.feed(ev, out);
  }
  const std::size_t used = whole * sizeof(input_event);
  std::memmove(mBuffer.data(), mBuffer.data() + used, mHave - used);  // keep a partial event (pipes)
  mHave -= used;
  return out.size() != before ? ReadResult::Events : ReadResult::Timeout;
}

}  // namespace fieldcast::io
