// Pose predictors are exact for motion of their own order.
#include <motion/PosePredictor.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace fieldcast::motion {
namespace {

TimePoint at(double s) { return TimePoint{fromSeconds(s)}; }

void expectPoseNear(const Pose& a, const Pose& b, double tol) {
  EXPECT_NEAR(a.positionM.x, b.positionM.x, tol);
  EXPECT_NEAR(a.positionM.y, b.positionM.y, tol);
  EXPECT_NEAR(a.positionM.z, b.positionM.z, tol);
  EXPECT_NEAR(std::remainder(a.headingRad - b.headingRad, 2 * std::numbers::pi), 0.0, tol);
  EXPECT_NEAR(a.pitchRad, b.pitchRad, tol);
  EXPECT_NEAR(std::remainder(a.rollRad - b.rollRad, 2 * std::numbers::pi), 0.0, tol);
}

// Linear motion whose heading crosses north (wraps from 2π to 0) during the samples.
Pose linearPose(double t) {
  double heading = radians(355.0) + radians(40.0) * t;
  heading = std::fmod(heading, 2 * std::numbers::pi);
  return Pose{{100.0 + 120.0 * t, -30.0 * t, 500.0 + 8.0 * t}, heading, radians(2.0) - 0.1 * t, 0.3 * t};
}

Pose quadraticPose(double t) {
  return Pose{{10.0 + 50.0 * t + 4.0 * t * t, 3.0 * t * t, 300.0 - 9.81 * 0.5 * t * t},
              0.2 + 0.1 * t + 0.05 * t * t,
              -0.02 * t * t,
              0.4 * t - 0.3 * t * t};
}

TEST(ConstantVelocityPredictor, IsExactForConstantVelocityAndRatesAcrossNorth) {
  ConstantVelocityPredictor p;
  EXPECT_EQ(p.poseAt(at(1.0)), Pose{});
  p.push(at(0.00), linearPose(0.00));
  EXPECT_EQ(p.poseAt(at(1.0)), linearPose(0.0));  // one sample: hold
  p.push(at(0.05), linearPose(0.05));
  p.push(at(0.10), linearPose(0.10));
  for (double t : {0.10, 0.1167, 0.15, 0.25, 0.5}) expectPoseNear(p.poseAt(at(t)), linearPose(t), 1e-9);
}

TEST(ConstantAccelerationPredictor, IsExactForConstantAcceleration) {
  ConstantAccelerationPredictor p;
  p.push(at(0.0), quadraticPose(0.0));
  p.push(at(0.04), quadraticPose(0.04));
  expectPoseNear(p.poseAt(at(0.04)), quadraticPose(0.04), 1e-12);
  p.push(at(0.1), quadraticPose(0.1));  // uneven spacing on purpose
  for (double t : {0.1, 0.12, 0.2, 0.4}) expectPoseNear(p.poseAt(at(t)), quadraticPose(t), 1e-8);
  // Constant velocity misses the curvature
  ConstantVelocityPredictor cv;
  cv.push(at(0.04), quadraticPose(0.04));
  cv.push(at(0.1), quadraticPose(0.1));
  EXPECT_GT(std::abs(cv.poseAt(at(0.4)).positionM.z - quadraticPose(0.4).positionM.z), 0.1);
}

TEST(PoseHistory, KeepsTheNewestSamplesAndReplacesSameTime) {
  PoseHistory h;
  for (int i = 0; i < 5; ++i) h.push(at(i), Pose{{double(i), 0, 0}, 0, 0, 0});
  EXPECT_EQ(h.size(), PoseHistory::kCapacity);
  EXPECT_EQ(h.fromNewest(0).pose.positionM.x, 4.0);
  EXPECT_EQ(h.fromNewest(2).pose.positionM.x, 2.0);
  h.push(at(4), Pose{{40.0, 0, 0}, 0, 0, 0});
  EXPECT_EQ(h.fromNewest(0).pose.positionM.x, 40.0);
  EXPECT_EQ(h.fromNewest(1).pose.positionM.x, 3.0);
}

}  // namespace
}  // namespace fieldcast::motion
