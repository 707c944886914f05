#include "CockpitActions.h"

namespace fieldcast::app {

using io::Discrete;

CockpitActions::CockpitActions(const motion::MotionSource& flight, io::CockpitButtons buttons, ResetFn reset)
    : mFlight(flight), mButtons(buttons), mReset(std::move(reset)) {}

TimePoint CockpitActions::flightTime(TimePoint t) const noexcept {
  const TimeMap m = mMap.load();
  return m.frozen != 0 ? TimePoint{Nanoseconds{m.heldAtNs}} : t - Nanoseconds{m.offsetNs};
}

bool CockpitActions::buttonPressed(int button, std::uint64_t now) const noexcept {
  if (button < 1 || button > 64) return false;
  const std::uint64_t bit = std::uint64_t{1} << (button - 1);
  return (now & bit) != 0 && (mLastButtons & bit) == 0;
}

void CockpitActions::beforeField(TimePoint fieldTime, const io::DiscreteSnapshot* discretes,
                                 std::uint64_t buttons) noexcept {
  if (mFirst) {  // what is held or counted before the first field is not a press
    mFirst = false;
    mLastButtons = buttons;
    if (discretes != nullptr) mLastDiscretes = *discretes;
  }
  const auto gpioPresses = [&](Discrete d) -> std::uint32_t {
    return discretes == nullptr ? 0u : discretes->pressCount(d) - mLastDiscretes.pressCount(d);
  };
  const std::uint32_t resets = gpioPresses(Discrete::Reset) + (buttonPressed(mButtons.reset, buttons) ? 1u : 0u);
  const std::uint32_t triggers = gpioPresses(Discrete::Trigger) + (buttonPressed(mButtons.trigger, buttons) ? 1u : 0u);
  if (buttonPressed(mButtons.freeze, buttons)) mToggled = !mToggled;
  const bool freeze = mToggled || (discretes != nullptr && discretes->isOn(Discrete::Freeze));
  mLastButtons = buttons;
  if (discretes != nullptr) mLastDiscretes = *discretes;

  TimeMap map = mMap.load();
  const std::int64_t t = fieldTime.time_since_epoch().count();
  if (freeze && map.frozen == 0) {
    map.heldAtNs = t - map.offsetNs;
    map.frozen = 1;
    mMap.store(map);
    mFreezes.fetch_add(1, std::memory_order_relaxed);
  } else if (!freeze && map.frozen != 0) {
    map.offsetNs = t - map.heldAtNs;  // the flight goes on from the instant it froze
    map.frozen = 0;
    mMap.store(map);
  }
  if (resets > 0) {
    if (mReset) mReset(flightTime(fieldTime));
    mResets.fetch_add(1, std::memory_order_relaxed);
  }
  if (triggers > 0) mTriggers.fetch_add(triggers, std::memory_order_relaxed);
}

CockpitFigures CockpitActions::figures() const noexcept {
  return {mFreezes.load(std::memory_order_relaxed), mResets.load(std::memory_order_relaxed),
          mTriggers.load(std::memory_order_relaxed)};
}

}  // namespace fieldcast::app
