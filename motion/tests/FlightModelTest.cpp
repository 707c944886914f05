#include <motion/FlightModel.h>

#include <gtest/gtest.h>

#include <cmath>
#include <thread>

namespace fieldcast::motion {
namespace {

constexpr TimePoint at(double seconds) { return TimePoint{Nanoseconds{static_cast<std::int64_t>(seconds * 1e9)}}; }

FlightModelParams steadyParams() {
  FlightModelParams p;
  p.minSpeedMps = p.maxSpeedMps = 100.0;  // throttle does nothing: constant airspeed
  return p;
}

TEST(FlightModel, HandsOffFliesStraightAndLevel) {
  FlightModel model(steadyParams(), Pose{{0, 0, 500}, 0, 0, 0}, 100.0, at(0));
  model.step(at(10), FlightControls{});
  const Pose p = model.state().pose;
  EXPECT_NEAR(p.positionM.y, 1000.0, 1e-6);
  EXPECT_NEAR(p.positionM.x, 0.0, 1e-9);
  EXPECT_NEAR(p.positionM.z, 500.0, 1e-9);
}

TEST(FlightModel, RightStickBanksRightAndTurnsRight) {
  FlightModel model(steadyParams(), Pose{{0, 0, 500}, 0, 0, 0}, 100.0, at(0));
  model.step(at(0.5), FlightControls{0.5, 0, 0, 0.5});  // roll in at 0.75 rad/s for 0.5 s
  model.step(at(10.5), FlightControls{});               // hold the bank
  const FlightState s = model.state();
  EXPECT_NEAR(s.pose.rollRad, 0.375, 1e-9);
  const double expectedRate = 9.80665 * std::tan(0.375) / 100.0;  // coordinated turn
  EXPECT_NEAR(s.headingRateRadS, expectedRate, 1e-12);
  EXPECT_GT(s.pose.headingRad, 10.0 * expectedRate * 0.99);  // turned right (clockwise)
  EXPECT_GT(s.pose.positionM.x, 0.0);                        // drifted east
}

TEST(FlightModel, ExtrapolationMatchesStepping) {
  // In a steady turn the pose predicted 20 ms ahead equals the pose stepped there.
  FlightModel a(steadyParams(), Pose{{0, 0, 500}, 0.3, 0.05, 0.4}, 100.0, at(0));
  FlightModel b(steadyParams(), Pose{{0, 0, 500}, 0.3, 0.05, 0.4}, 100.0, at(0));
  a.step(at(1.0), FlightControls{});
  b.step(at(1.0), FlightControls{});
  const Pose predicted = a.poseAt(at(1.02));
  b.step(at(1.02), FlightControls{});
  const Pose stepped = b.state().pose;
  EXPECT_NEAR(predicted.headingRad, stepped.headingRad, 1e-9);
  EXPECT_NEAR(predicted.positionM.x, stepped.positionM.x, 0.01);  // chord vs arc over 2 m
  EXPECT_NEAR(predicted.positionM.y, stepped.positionM.y, 0.01);
}

TEST(FlightModel, ThrottleSetsAirspeedWithALag) {
  FlightModelParams p;
  p.minSpeedMps = 50.0;
  p.maxSpeedMps = 250.0;
  p.speedTimeConstantS = 2.0;
  FlightModel model(p, Pose{{0, 0, 500}, 0, 0, 0}, 50.0, at(0));
  model.step(at(2.0), FlightControls{0, 0, 0, 1.0});
  EXPECT_NEAR(model.state().speedMps, 250.0 - 200.0 * std::exp(-1.0), 0.01);
}

TEST(FlightModel, NeverGoesBelowTheTerrainClearance) {
  FlightModelParams p = steadyParams();
  p.minClearanceM = 20.0;
  auto ridge = [](double x, double) { return 100.0 + 0.5 * x; };  // rising ground to the east
  FlightModel model(p, Pose{{0, 0, 150}, radians(90.0), radians(-20.0), 0}, 100.0, at(0), ridge);
  for (int i = 1; i <= 400; ++i) {
    model.step(at(i * 0.025), FlightControls{0, -1.0, 0, 0.5});  // full nose-down
    const Pose pose = model.state().pose;
    EXPECT_GE(pose.positionM.z, ridge(pose.positionM.x, 0) + 20.0 - 1e-9);
  }
}

TEST(FlightModel, LimitsBankAndPitch) {
  FlightModelParams p = steadyParams();
  FlightModel model(p, Pose{{0, 0, 3000}, 0, 0, 0}, 100.0, at(0));
  model.step(at(5.0), FlightControls{1.0, 1.0, 0, 0.5});
  EXPECT_NEAR(model.state().pose.rollRad, p.maxBankRad, 1e-12);
  EXPECT_NEAR(model.state().pose.pitchRad, p.maxPitchRad, 1e-12);
  EXPECT_EQ(model.state().rollRateRadS, 0.0);
}

TEST(FlightModel, PoseAtIsSafeWhileStepping) {
  FlightModel model(steadyParams(), Pose{{0, 0, 500}, 0, 0, 0.2}, 100.0, at(0));
  std::atomic<bool> done{false};
  std::thread reader([&] {
    while (!done) {
      const Pose p = model.poseAt(at(0.01));
      ASSERT_TRUE(std::isfinite(p.positionM.y));
    }
  });
  for (int i = 1; i <= 2000; ++i) model.step(at(i * 0.001), FlightControls{0.1, 0, 0, 0.5});
  done = true;
  reader.join();
}

}  // namespace
}  // namespace fieldcast::motion
