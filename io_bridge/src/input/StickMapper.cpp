#include <io_bridge/StickMapper.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace fieldcast::io {
namespace {

double applyExpo(double x, double e) noexcept { return (1.0 - e) * x + e * x * x * x; }

}  // namespace

double shapeBipolar(std::int32_t raw, const AxisCalibration& c) noexcept {
  const double v = raw;
  double x = 0.0;
  if (v >= c.center) {
    x = c.max > c.center ? (v - c.center) / (static_cast<double>(c.max) - c.center) : 0.0;
  } else {
    x = c.center > c.min ? (v - c.center) / (static_cast<double>(c.center) - c.min) : 0.0;
  }
  x = std::clamp(x, -1.0, 1.0);
  if (c.invert) x = -x;
  const double mag = std::abs(x);
  if (mag <= c.deadZone) return 0.0;
  const double scaled = (mag - c.deadZone) / (1.0 - c.deadZone);  // continuous at the dead-zone edge
  return std::copysign(applyExpo(scaled, c.expo), x);
}

double shapeUnipolar(std::int32_t raw, const AxisCalibration& c) noexcept {
  if (c.max <= c.min) return 0.0;
  double u = std::clamp((static_cast<double>(raw) - c.min) / (static_cast<double>(c.max) - c.min), 0.0, 1.0);
  if (c.invert) u = 1.0 - u;
  if (c.deadZone > 0.0) {
    // The travel left between the two dead zones; none at 0.5 (a profile may ask it): a switch at
    // the middle, not 0/0
    const double travel = 1.0 - 2.0 * c.deadZone;
    u = travel > 0.0 ? std::clamp((u - c.deadZone) / travel, 0.0, 1.0) : (u > 0.5 ? 1.0 : 0.0);
  }
  return u;
}

StickMapper::StickMapper(const DeviceDescription& device, const StickProfile& profile)
    : mDevice(device), mProfile(profile) {
  const std::size_t n = mDevice.controls.size();
  for (std::size_t i = 0; i < n; ++i) mIndex.emplace_back(mDevice.controls[i].usage, static_cast<int>(i));
  std::sort(mIndex.begin(), mIndex.end());
  mRaw.assign(n, 0);
  mSeen.assign(n, false);
  mButtonBit.assign(n, -1);
  for (std::size_t i = 0; i < kAxisRoles; ++i) {
    const AxisBinding& b = mProfile.axes[i];
    for (const Usage u : b.controls) {
      const int ci = indexOf(u);
      if (ci < 0) continue;
      const ControlInfo& info = mDevice.controls[static_cast<std::size_t>(ci)];
      AxisCalibration& c = mBound[i].cal;
      c.min = b.min.value_or(info.min);
      c.max = b.max.value_or(info.max);
      c.center = b.center.value_or(static_cast<std::int32_t>((std::int64_t{c.min} + c.max + 1) / 2));
      c.invert = b.invert;
      c.deadZone = b.deadZone;
      c.expo = b.expo;
      mBound[i].control = ci;
      break;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Usage u = mDevice.controls[i].usage;
    if (usagePage(u) != usages::kButtonPage) continue;
    const std::uint16_t deviceButton = usageId(u);
    int bit = -1;
    if (mProfile.buttonOrder.empty()) {
      if (deviceButton >= 1 && deviceButton <= 64) bit = deviceButton - 1;
    } else {
      const auto it = std::find(mProfile.buttonOrder.begin(), mProfile.buttonOrder.end(), deviceButton);
      if (it != mProfile.buttonOrder.end()) bit = static_cast<int>(it - mProfile.buttonOrder.begin());
    }
    mButtonBit[i] = static_cast<std::int8_t>(bit);
  }
  mState.throttle = mProfile.defaultThrottle;
}

int StickMapper::indexOf(Usage usage) const noexcept {
  const auto it = std::lower_bound(mIndex.begin(), mIndex.end(), std::pair<Usage, int>{usage, -1});
  return it != mIndex.end() && it->first == usage ? it->second : -1;
}

double StickMapper::axisValue(AxisRole role) const noexcept {
  const Bound& b = mBound[static_cast<std::size_t>(role)];
  const bool throttle = role == AxisRole::Throttle;
  if (b.control < 0 || !mSeen[static_cast<std::size_t>(b.control)]) return throttle ? mProfile.defaultThrottle : 0.0;
  const std::int32_t raw = mRaw[static_cast<std::size_t>(b.control)];
  return throttle ? shapeUnipolar(raw, b.cal) : shapeBipolar(raw, b.cal);
}

bool StickMapper::apply(const InputEvent& e) noexcept {
  switch (e.type) {
    case InputEventType::Value: {
      const int ci = indexOf(e.usage);
      if (ci < 0) return false;
      const auto i = static_cast<std::size_t>(ci);
      mRaw[i] = e.value;
      mSeen[i] = true;
      if (mButtonBit[i] >= 0) {
        const std::uint64_t bit = std::uint64_t{1} << mButtonBit[i];
        mButtons = e.value != 0 ? (mButtons | bit) : (mButtons & ~bit);
      }
      if (e.usage == usages::kHatSwitch) mHat = e.value;
      return false;
    }
    case InputEventType::Sync:
      mState.time = TimePoint{Nanoseconds{e.tNs}};
      mState.roll = axisValue(AxisRole::Roll);
      mState.pitch = axisValue(AxisRole::Pitch);
      mState.yaw = axisValue(AxisRole::Yaw);
      mState.throttle = axisValue(AxisRole::Throttle);
      mState.buttons = mButtons;
      mState.hat = mHat;
      mState.health = InputHealth::Live;
      mState.lostAt = TimePoint{};
      return true;
    case InputEventType::DeviceLost:
    case InputEventType::DeviceFound: return false;
  }
  return false;
}

std::string StickMapper::describeBindings() const {
  std::ostringstream os;
  os << "profile \"" << mProfile.name << "\" on \"" << mDevice.name << "\"";
  for (std::size_t i = 0; i < kAxisRoles; ++i) {
    const Bound& b = mBound[i];
    os << "\n  " << axisRoleName(static_cast<AxisRole>(i)) << ": ";
    if (b.control < 0) {
      os << "unbound";
      continue;
    }
    os << usageName(mDevice.controls[static_cast<std::size_t>(b.control)].usage) << " [" << b.cal.min << ", "
       << b.cal.max << "] centre " << b.cal.center << (b.cal.invert ? " inverted" : "") << " dead zone "
       << b.cal.deadZone << " expo " << b.cal.expo;
  }
  return os.str();
}

}  // namespace fieldcast::io
