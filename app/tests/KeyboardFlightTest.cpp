#include "KeyboardFlight.h"

#include <gtest/gtest.h>

namespace fieldcast::app {
namespace {

using namespace std::chrono_literals;

TEST(KeyboardFlight, APressDeflectsFullyThenFadesToNeutral) {
  KeyboardFlight keys;
  const TimePoint t{10s};
  EXPECT_EQ(keys.controlsAt(t).roll, 0.0);
  keys.onKey(io::WindowKey::Right, t);
  EXPECT_EQ(keys.controlsAt(t + 100ms).roll, 1.0);
  EXPECT_NEAR(keys.controlsAt(t + 375ms).roll, 0.5, 1e-9);
  EXPECT_EQ(keys.controlsAt(t + 600ms).roll, 0.0);
  EXPECT_EQ(keys.lastInputTime(), t);
}

TEST(KeyboardFlight, AutoRepeatOfAHeldKeyHoldsTheDeflection) {
  KeyboardFlight keys;
  TimePoint t{10s};
  for (int k = 0; k < 30; ++k, t += 33ms) keys.onKey(io::WindowKey::Up, t);
  EXPECT_EQ(keys.controlsAt(t).pitch, -1.0);  // up arrow: stick forward, nose down
}

TEST(KeyboardFlight, ThrottleStepsAndStaysWithinRange) {
  KeyboardFlight keys;
  const TimePoint t{1s};
  for (int k = 0; k < 8; ++k) keys.onKey(io::WindowKey::Faster, t);
  EXPECT_EQ(keys.controlsAt(t + 10s).throttle, 1.0);
  keys.onKey(io::WindowKey::Slower, t);
  EXPECT_NEAR(keys.controlsAt(t).throttle, 0.9, 1e-9);
  keys.onKey(io::WindowKey::Left, t);
  keys.onKey(io::WindowKey::Reset, t);
  EXPECT_EQ(keys.controlsAt(t).roll, 0.0);
}

}  // namespace
}  // namespace fieldcast::app
