#pragma once
// Flying with the keyboard of the live window when no stick is present. A window only reports
// key presses (held keys auto-repeat at some 30 Hz), so each press of an arrow deflects that
// axis fully and the deflection fades out over a short hold time: a held key keeps the axis
// deflected, a tap gives a short nudge. + and − step the throttle; R levels the wings.

#include <fieldcast/SeqLock.h>
#include <fieldcast/Time.h>
#include <io_bridge/WindowSink.h>
#include <motion/FlightModel.h>

namespace fieldcast::app {

class KeyboardFlight {
 public:
  static constexpr double kHoldS = 0.25;  ///< a press deflects its axis fully for this long, then fades

  /// A key pressed at `now` (the window's thread). RT-safe.
  void onKey(io::WindowKey key, TimePoint now) noexcept;
  /// The controls at `now` (any thread, lock-free). RT-safe.
  motion::FlightControls controlsAt(TimePoint now) const noexcept;
  /// Instant of the newest key press that moved a control (for stick → field latency); zero if none.
  TimePoint lastInputTime() const noexcept { return mState.load().lastPress; }

 private:
  struct State {
    TimePoint rollPress{}, pitchPress{}, lastPress{};
    double rollSign = 0.0;
    double pitchSign = 0.0;
    double throttle = 0.5;
  };
  SeqLock<State> mState;
};

}  // namespace fieldcast::app
