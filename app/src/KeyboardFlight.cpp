#include "KeyboardFlight.h"

#include <algorithm>

namespace fieldcast::app {
namespace {

// Full deflection for kHoldS after the press, then a linear fade over the same time.
double deflection(double sign, TimePoint press, TimePoint now) noexcept {
  if (sign == 0.0 || now < press) return 0.0;
  const double age = toSeconds(now - press);
  const double hold = KeyboardFlight::kHoldS;
  if (age <= hold) return sign;
  return sign * std::max(0.0, 1.0 - (age - hold) / hold);
}

}  // namespace

void KeyboardFlight::onKey(io::WindowKey key, TimePoint now) noexcept {
  State s = mState.load();
  switch (key) {
    case io::WindowKey::Left: s.rollSign = -1.0, s.rollPress = now; break;
    case io::WindowKey::Right: s.rollSign = 1.0, s.rollPress = now; break;
    case io::WindowKey::Up: s.pitchSign = -1.0, s.pitchPress = now; break;  // stick forward: nose down
    case io::WindowKey::Down: s.pitchSign = 1.0, s.pitchPress = now; break;
    case io::WindowKey::Faster: s.throttle = std::min(1.0, s.throttle + 0.1); break;
    case io::WindowKey::Slower: s.throttle = std::max(0.0, s.throttle - 0.1); break;
    case io::WindowKey::Reset: s.rollSign = s.pitchSign = 0.0; break;
    default: return;
  }
  s.lastPress = now;
  mState.store(s);
}

motion::FlightControls KeyboardFlight::controlsAt(TimePoint now) const noexcept {
  const State s = mState.load();
  motion::FlightControls c;
  c.roll = deflection(s.rollSign, s.rollPress, now);
  c.pitch = deflection(s.pitchSign, s.pitchPress, now);
  c.throttle = s.throttle;
  return c;
}

}  // namespace fieldcast::app
