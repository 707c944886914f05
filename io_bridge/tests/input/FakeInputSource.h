#pragma once
// A scripted input source for tests: delivers queued frames one per read(), then ends or is lost.

#include <io_bridge/InputSource.h>

#include <deque>
#include <vector>

namespace fieldcast::io::testing {

class FakeInputSource final : public InputSource {
 public:
  FakeInputSource(DeviceDescription device, std::deque<std::vector<InputEvent>> frames, ReadResult atEnd)
      : mDevice(std::move(device)), mFrames(std::move(frames)), mAtEnd(atEnd) {}
  const DeviceDescription& description() const noexcept override { return mDevice; }
  ReadResult read(std::vector<InputEvent>& out, Nanoseconds) override {
    if (mFrames.empty()) return mAtEnd;
    out.insert(out.end(), mFrames.front().begin(), mFrames.front().end());
    mFrames.pop_front();
    return ReadResult::Events;
  }

 private:
  DeviceDescription mDevice;
  std::deque<std::vector<InputEvent>> mFrames;
  ReadResult mAtEnd;
};

/// A frame: values then a Sync at tNs.
inline std::vector<InputEvent> frame(std::int64_t tNs, std::initializer_list<std::pair<Usage, std::int32_t>> values) {
  std::vector<InputEvent> f;
  for (const auto& [u, v] : values) f.push_back(InputEvent{tNs, u, v, InputEventType::Value});
  f.push_back(InputEvent{tNs, 0, 0, InputEventType::Sync});
  return f;
}

/// A plain joystick: X/Y/Rz 0..1023, throttle 0..255, 8 buttons, a hat.
inline DeviceDescription plainStick() {
  using namespace usages;
  DeviceDescription d;
  d.name = "Test Stick";
  d.controls = {{kX, ControlKind::Axis, 0, 1023},
                {kY, ControlKind::Axis, 0, 1023},
                {kRz, ControlKind::Axis, 0, 1023},
                {kThrottle, ControlKind::Axis, 0, 255},
                {kHatSwitch, ControlKind::Hat, 0, kHatCentred}};
  for (std::uint16_t b = 1; b <= 8; ++b) d.controls.push_back({button(b), ControlKind::Button, 0, 1});
  return d;
}

}  // namespace fieldcast::io::testing
