#pragma once
// The cockpit's freeze, reset and trigger, from the GPIO discretes and the stick buttons the
// profile maps ([buttons] freeze/reset/trigger), acted on once per field by the field thread.
//
// - Freeze: the GPIO discrete is a switch (frozen while it is on); the stick button toggles on
//   each press (buttons are momentary). Frozen while either says so. While frozen the ownship pose
//   is held — fields keep coming, the picture is still — and the flight's own time stops, so on
//   release the flight resumes from where it froze, without a jump.
// - Reset: each press (GPIO press count, button rising edge) calls the reset action with the
//   flight's current time: the service restarts the scripted flight at time 0 there, or puts the
//   stick flight model back at its start pose and speed.
// - Trigger: presses are counted, nothing else.
//
// A press is a rising edge: a button held across fields acts once; what is held or already
// counted when the first field runs is not acted on. GPIO presses are counted by the GPIO thread,
// so none is missed; a stick button is sampled once per field, so a press shorter than a field
// (under 17 ms, shorter than any real press) can be missed.
//
// This is the ownship the channel sees: poseAt(t) asks the wrapped source at the flight's time,
// which is t shifted by the time spent frozen, or the instant of the freeze while frozen.

#include <io_bridge/GpioInput.h>
#include <io_bridge/StickProfile.h>
#include <motion/MotionSource.h>

#include <fieldcast/SeqLock.h>
#include <fieldcast/Time.h>

#include <atomic>
#include <cstdint>
#include <functional>

namespace fieldcast::app {

/// What the cockpit has done so far (any thread, for the run summary).
struct CockpitFigures {
  std::uint64_t freezes = 0;   ///< times the pose was frozen
  std::uint64_t resets = 0;    ///< resets acted on
  std::uint64_t triggers = 0;  ///< trigger presses
};

class CockpitActions final : public motion::MotionSource {
 public:
  /// Called on the field thread with the flight's time at the field; must be RT-safe.
  using ResetFn = std::function<void(TimePoint flightTime)>;

  CockpitActions(const motion::MotionSource& flight, io::CockpitButtons buttons, ResetFn reset);

  /// Once per field, before the field's pose is asked for: reads the discretes (null: no GPIO)
  /// and the stick's buttons (ControlState::buttons) and acts on them at the field's display
  /// time. Field thread only. RT-safe.
  void beforeField(TimePoint fieldTime, const io::DiscreteSnapshot* discretes, std::uint64_t buttons) noexcept;

  /// The flight's time at real instant `t`: t less the time spent frozen; while frozen, the
  /// instant of the freeze. Any thread, RT-safe.
  TimePoint flightTime(TimePoint t) const noexcept;
  bool frozen() const noexcept { return mMap.load().frozen; }
  /// The wrapped flight at flightTime(t). Any thread, RT-safe.
  Pose poseAt(TimePoint t) const noexcept override { return mFlight.poseAt(flightTime(t)); }

  CockpitFigures figures() const noexcept;

 private:
  struct TimeMap {
    std::int64_t offsetNs = 0;  // flight time = t − offset while running
    std::int64_t heldAtNs = 0;  // flight time while frozen
    std::int64_t frozen = 0;    // 0/1, a word so the struct has no padding
  };
  bool buttonPressed(int button, std::uint64_t now) const noexcept;

  const motion::MotionSource& mFlight;
  io::CockpitButtons mButtons;
  ResetFn mReset;
  SeqLock<TimeMap> mMap;
  // Field thread only.
  bool mFirst = true;
  bool mToggled = false;
  std::uint64_t mLastButtons = 0;
  io::DiscreteSnapshot mLastDiscretes{};
  // Read by the summary.
  std::atomic<std::uint64_t> mFreezes{0}, mResets{0}, mTriggers{0};
};

}  // namespace fieldcast::app
