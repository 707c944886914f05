#include <motion/ScriptedTrajectory.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

namespace fieldcast::motion {
namespace {

Waypoint at(double t, double x, double y, double z) { return Waypoint{t, {x, y, z}, {}, {}, {}}; }

TEST(ScriptedTrajectory, StraightLevelFlightFollowsItsTrack) {
  const ScriptedTrajectory north("north", {at(0, 0, 0, 500), at(10, 0, 1000, 500), at(20, 0, 2000, 500)});
  const Pose p = north.poseAtSeconds(5.0);
  EXPECT_NEAR(p.positionM.y, 500.0, 1e-9);
  EXPECT_NEAR(p.headingRad, 0.0, 1e-12);
  EXPECT_NEAR(p.pitchRad, 0.0, 1e-12);
  EXPECT_NEAR(p.rollRad, 0.0, 1e-12);
  const ScriptedTrajectory east("east", {at(0, 0, 0, 500), at(10, 1000, 0, 500)});
  EXPECT_NEAR(east.poseAtSeconds(3.0).headingRad, std::numbers::pi / 2, 1e-12);
  // Beyond the last waypoint the flight goes on straight at the same speed.
  EXPECT_NEAR(east.poseAtSeconds(12.0).positionM.x, 1200.0, 1e-9);
}

TEST(ScriptedTrajectory, ClimbSetsPitchPlusCameraOffset) {
  const ScriptedTrajectory climb("climb", {at(0, 0, 0, 0), at(10, 0, 1000, 100)}, radians(-10.0));
  EXPECT_NEAR(climb.poseAtSeconds(5.0).pitchRad, std::atan2(10.0, 100.0) - radians(10.0), 1e-12);
}

TEST(ScriptedTrajectory, RightTurnBanksRightAsACoordinatedTurn) {
  // Clockwise circle seen from above (a right turn), radius 1000 m at 100 m/s: ω = 0.1 rad/s.
  const double radius = 1000.0, speed = 100.0, omega = speed / radius;
  std::vector<Waypoint> wps;
  for (int i = 0; i <= 40; ++i) {
    const double t = i * 1.0, a = omega * t;  // heading = a: starts north, turns east
    wps.push_back(at(t, radius * (1.0 - std::cos(a)), radius * std::sin(a), 800.0));
  }
  const ScriptedTrajectory turn("turn", wps);
  const Pose p = turn.poseAtSeconds(20.0);
  EXPECT_NEAR(p.headingRad, omega * 20.0, radians(0.1));
  const double expectedRoll = std::atan(speed * omega / 9.80665);  // ≈ 45.6°
  EXPECT_GT(p.rollRad, 0.0);
  EXPECT_NEAR(p.rollRad, expectedRoll, radians(0.5));
}

TEST(ScriptedTrajectory, GivenHeadingsTurnTheShortWay) {
  std::vector<Waypoint> wps{at(0, 0, 0, 100), at(10, 0, 100, 100)};
  wps[0].headingRad = radians(350.0);
  wps[1].headingRad = radians(10.0);
  const ScriptedTrajectory t("wrap", wps);
  EXPECT_NEAR(std::remainder(t.poseAtSeconds(5.0).headingRad, 2 * std::numbers::pi), 0.0, 1e-9);
}

TEST(ScriptedTrajectory, AnglesMustBeOnEveryWaypointOrNone) {
  std::vector<Waypoint> wps{at(0, 0, 0, 100), at(10, 0, 100, 100)};
  wps[0].rollRad = 0.2;
  EXPECT_THROW(ScriptedTrajectory("mixed", wps), std::invalid_argument);
  EXPECT_THROW(ScriptedTrajectory("one", {at(0, 0, 0, 0)}), std::invalid_argument);
  EXPECT_THROW(ScriptedTrajectory("back", {at(1, 0, 0, 0), at(1, 0, 0, 0)}), std::invalid_argument);
}

TEST(ScriptedTrajectory, PoseAtUsesTheStartTime) {
  ScriptedTrajectory north("north", {at(0, 0, 0, 500), at(10, 0, 1000, 500)});
  north.setStartTime(TimePoint{Nanoseconds{5'000'000'000}});
  EXPECT_NEAR(north.poseAt(TimePoint{Nanoseconds{7'500'000'000}}).positionM.y, 250.0, 1e-9);
}

std::string writeFlight(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("fieldcast_flight_" + name + ".toml");
  std::ofstream(path) << text;
  return path.string();
}

TEST(ScriptedTrajectory, LoadsAFlightFile) {
  const auto path = writeFlight("ok", R"(name = "test"
camera_pitch_deg = -5
[[waypoint]]
t = 0
position = [0, 0, 300]
[[waypoint]]
t = 10
position = [0, 1000, 300]
)");
  const auto flight = ScriptedTrajectory::load(path);
  EXPECT_EQ(flight.name(), "test");
  EXPECT_EQ(flight.durationS(), 10.0);
  EXPECT_NEAR(flight.poseAtSeconds(5).pitchRad, radians(-5.0), 1e-12);
}

TEST(ScriptedTrajectory, FileErrorsNameFileLineAndKey) {
  const auto path =
      writeFlight("bad", "[[waypoint]]\nt = 0\nposition = [0, 0]\n[[waypoint]]\nt = 1\nposition = [0,0,0]\n");
  try {
    (void)ScriptedTrajectory::load(path);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(
        std::string(e.what()).find(path + ":3: waypoint[1].position: expected an array of 3 numbers, got [ 0, 0 ]"),
        std::string::npos)
        << e.what();
  }
  const auto unknown = writeFlight("unknown", "speed = 3\n");
  EXPECT_THROW((void)ScriptedTrajectory::load(unknown), std::runtime_error);
}

}  // namespace
}  // namespace fieldcast::motion
