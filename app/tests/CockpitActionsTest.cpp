#include "CockpitActions.h"

#include <motion/FlightModel.h>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <atomic>

namespace fieldcast::app {
namespace {

using namespace std::chrono_literals;
using io::Discrete;

constexpr Nanoseconds kField = 20ms;

// A scripted flight in miniature: x is the seconds flown since its start (east at 1 m/s).
class LineFlight final : public motion::MotionSource {
 public:
  void setStart(TimePoint t) noexcept { mStartNs.store(t.time_since_epoch().count()); }
  Pose poseAt(TimePoint t) const noexcept override {
    Pose p;
    p.positionM.x = toSeconds(t - TimePoint{Nanoseconds{mStartNs.load()}});
    return p;
  }

 private:
  std::atomic<std::int64_t> mStartNs{0};
};

struct Rig {
  LineFlight flight;
  CockpitActions cockpit;
  io::DiscreteSnapshot gpio;
  TimePoint t{100s};

  explicit Rig(io::CockpitButtons buttons = {})
      : cockpit(flight, buttons, [this](TimePoint flightNow) { flight.setStart(flightNow); }) {
    flight.setStart(t);
  }
  // One field with these buttons held; returns the pose the field shows.
  double field(std::uint64_t buttons = 0) {
    t += kField;
    cockpit.beforeField(t, &gpio, buttons);
    return cockpit.poseAt(t).positionM.x;
  }
  void gpioPress(Discrete d) { ++gpio.presses[static_cast<std::size_t>(d)]; }
  void gpioLevel(Discrete d, bool on) { gpio.level[static_cast<std::size_t>(d)] = on; }
};

std::uint64_t button(int n) { return std::uint64_t{1} << (n - 1); }

TEST(CockpitActions, GpioFreezeHoldsThePoseAcrossFieldsWhileFieldsContinue) {
  Rig rig;
  for (int k = 0; k < 10; ++k) rig.field();
  rig.gpioLevel(Discrete::Freeze, true);
  const double held = rig.field();
  EXPECT_NEAR(held, 0.22, 1e-9);
  for (int k = 0; k < 50; ++k) EXPECT_EQ(rig.field(), held) << "field " << k;
  EXPECT_TRUE(rig.cockpit.frozen());
  // Frames rendered ahead of the field see the held pose too: a still scene.
  EXPECT_EQ(rig.cockpit.poseAt(rig.t + 100ms).positionM.x, held);
  EXPECT_EQ(rig.cockpit.figures().freezes, 1u);
}

TEST(CockpitActions, UnfreezeResumesWhereTheFlightFroze) {
  Rig rig;
  for (int k = 0; k < 10; ++k) rig.field();
  rig.gpioLevel(Discrete::Freeze, true);
  const double held = rig.field();
  for (int k = 0; k < 100; ++k) rig.field();  // 2 s frozen
  rig.gpioLevel(Discrete::Freeze, false);
  EXPECT_NEAR(rig.field(), held, 1e-9);  // no jump over the frozen time
  EXPECT_NEAR(rig.field(), held + 0.02, 1e-9);
  EXPECT_FALSE(rig.cockpit.frozen());
  EXPECT_NEAR(rig.cockpit.poseAt(rig.t + 1s).positionM.x, held + 1.02, 1e-9);
}

TEST(CockpitActions, GpioResetReturnsTheFlightToItsStart) {
  Rig rig;
  for (int k = 0; k < 250; ++k) rig.field();
  EXPECT_NEAR(rig.cockpit.poseAt(rig.t).positionM.x, 5.0, 1e-9);
  rig.gpioPress(Discrete::Reset);
  EXPECT_NEAR(rig.field(), 0.0, 1e-9);
  EXPECT_NEAR(rig.field(), 0.02, 1e-9);  // and flies on from there
  EXPECT_EQ(rig.cockpit.figures().resets, 1u);
}

TEST(CockpitActions, ResetWhileFrozenHoldsTheStart) {
  Rig rig;
  for (int k = 0; k < 50; ++k) rig.field();
  rig.gpioLevel(Discrete::Freeze, true);
  rig.field();
  rig.gpioPress(Discrete::Reset);
  EXPECT_NEAR(rig.field(), 0.0, 1e-9);
  EXPECT_NEAR(rig.field(), 0.0, 1e-9);
  rig.gpioLevel(Discrete::Freeze, false);
  rig.field();
  EXPECT_NEAR(rig.field(), 0.02, 1e-9);
}

TEST(CockpitActions, ResetPutsTheStickFlightModelBackAtItsStartPoseAndSpeed) {
  Pose start;
  start.positionM = {1000.0, 2000.0, 500.0};
  start.headingRad = 0.5;
  const TimePoint t0{100s};
  motion::FlightModel model(motion::FlightModelParams{}, start, 80.0, t0);
  CockpitActions cockpit(model, io::CockpitButtons{0, 3, 0}, [&](TimePoint now) { model.reset(start, 80.0, now); });
  TimePoint t = t0;
  for (int k = 0; k < 100; ++k) {  // bank and climb at full throttle for 2 s
    t += kField;
    cockpit.beforeField(t, nullptr, 0);
    model.step(cockpit.flightTime(t), motion::FlightControls{1.0, 1.0, 0.0, 1.0});
  }
  ASSERT_GT(std::abs(model.state().pose.rollRad), 0.5);
  t += kField;
  cockpit.beforeField(t, nullptr, button(3));
  model.step(cockpit.flightTime(t), motion::FlightControls{1.0, 1.0, 0.0, 1.0});
  EXPECT_EQ(cockpit.poseAt(t), start);
  EXPECT_EQ(model.state().speedMps, 80.0);
  EXPECT_EQ(model.state().rollRateRadS, 0.0);   // rates start over too: nothing is extrapolated
  const Pose ahead = cockpit.poseAt(t + 50ms);  // straight and level at the start speed
  EXPECT_EQ(ahead.rollRad, start.rollRad);
  EXPECT_EQ(ahead.headingRad, start.headingRad);
  EXPECT_NEAR(glm::length(ahead.positionM - start.positionM), 80.0 * 0.05, 1e-9);
}

TEST(CockpitActions, AHeldButtonActsOnce) {
  Rig rig(io::CockpitButtons{0, 2, 1});
  for (int k = 0; k < 100; ++k) rig.field();
  const double fromStart = rig.field(button(2) | button(1));
  EXPECT_NEAR(fromStart, 0.0, 1e-9);
  for (int k = 1; k <= 20; ++k) EXPECT_NEAR(rig.field(button(2) | button(1)), 0.02 * k, 1e-9);  // held: no new reset
  EXPECT_EQ(rig.cockpit.figures().resets, 1u);
  EXPECT_EQ(rig.cockpit.figures().triggers, 1u);
  rig.field(0);
  rig.field(button(1));
  EXPECT_EQ(rig.cockpit.figures().triggers, 2u);
}

TEST(CockpitActions, TheStickFreezeButtonTogglesOnEachPress) {
  Rig rig(io::CockpitButtons{5, 0, 0});
  for (int k = 0; k < 10; ++k) rig.field();
  const double held = rig.field(button(5));
  EXPECT_TRUE(rig.cockpit.frozen());
  for (int k = 0; k < 10; ++k) EXPECT_EQ(rig.field(button(5)), held);  // held down
  for (int k = 0; k < 10; ++k) EXPECT_EQ(rig.field(0), held);          // released: still frozen
  EXPECT_NEAR(rig.field(button(5)), held, 1e-9);                       // pressed again: resumes
  EXPECT_FALSE(rig.cockpit.frozen());
  EXPECT_NEAR(rig.field(0), held + 0.02, 1e-9);
}

TEST(CockpitActions, GpioTriggerPressesAreCountedAndMoveNothing) {
  Rig rig;
  for (int k = 0; k < 10; ++k) rig.field();
  rig.gpioPress(Discrete::Trigger);
  rig.gpioPress(Discrete::Trigger);
  rig.gpioPress(Discrete::Trigger);
  EXPECT_NEAR(rig.field(), 0.22, 1e-9);
  EXPECT_EQ(rig.cockpit.figures().triggers, 3u);
  EXPECT_EQ(rig.cockpit.figures().resets, 0u);
  EXPECT_FALSE(rig.cockpit.frozen());
}

TEST(CockpitActions, WhatIsHeldOrCountedBeforeTheFirstFieldIsNotAPress) {
  Rig rig(io::CockpitButtons{0, 2, 0});
  rig.gpio.presses = {4, 4, 4};
  for (int k = 0; k < 50; ++k) rig.field(button(2));
  EXPECT_NEAR(rig.cockpit.poseAt(rig.t).positionM.x, 1.0, 1e-9);
  EXPECT_EQ(rig.cockpit.figures().resets, 0u);
  EXPECT_EQ(rig.cockpit.figures().triggers, 0u);
}

TEST(CockpitActions, UnmappedButtonsDoNothing) {
  Rig rig;  // no [buttons] freeze/reset/trigger
  for (int k = 0; k < 10; ++k) rig.field();
  for (int k = 0; k < 10; ++k) rig.field(~std::uint64_t{0});
  EXPECT_NEAR(rig.field(0), 0.42, 1e-9);
  EXPECT_EQ(rig.cockpit.figures().resets + rig.cockpit.figures().triggers + rig.cockpit.figures().freezes, 0u);
}

}  // namespace
}  // namespace fieldcast::app
