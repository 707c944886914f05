#include <motion/ScriptedTrajectory.h>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
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
  // Before the first waypoint the flight comes in straight at the same speed.
  EXPECT_NEAR(east.poseAtSeconds(-2.0).positionM.x, -200.0, 1e-9);
}

// Largest difference of two poses' positions (m) and angles (rad, modulo 2π).
double poseGap(const Pose& a, const Pose& b) {
  const double angle = std::max({std::abs(std::remainder(a.headingRad - b.headingRad, 2 * std::numbers::pi)),
                                 std::abs(a.pitchRad - b.pitchRad), std::abs(a.rollRad - b.rollRad)});
  return std::max(glm::length(a.positionM - b.positionM), angle);
}

// Continuity of position, velocity and (through the coordinated-turn roll) curvature at `s`.
void expectSmoothAt(const ScriptedTrajectory& f, double s, const char* where) {
  constexpr double kEps = 1e-8;  // a jump shows at any step; a smooth change shrinks with it
  const Pose before = f.poseAtSeconds(s - kEps), after = f.poseAtSeconds(s + kEps);
  EXPECT_LT(glm::length(before.positionM - after.positionM), 1e-3) << where;
  EXPECT_LT(glm::length(f.velocityAtSeconds(s - kEps) - f.velocityAtSeconds(s + kEps)), 1e-3) << where;
  EXPECT_LT(std::abs(std::remainder(before.headingRad - after.headingRad, 2 * std::numbers::pi)), 1e-5) << where;
  EXPECT_LT(std::abs(before.rollRad - after.rollRad), 1e-5) << where;
  EXPECT_LT(std::abs(before.pitchRad - after.pitchRad), 1e-5) << where;
}

TEST(ScriptedTrajectory, AnOpenFlightLoopsSmoothlyBackToItsStart) {
  // North at 100 m/s for 20 s, climbing a little: the leg back must turn round, not fly on.
  const ScriptedTrajectory north("north", {at(0, 0, 0, 500), at(10, 0, 1000, 520), at(20, 0, 2000, 560)});
  ASSERT_EQ(north.end(), FlightEnd::Loop);
  const double lap = north.lapS();
  ASSERT_GT(lap, 20.0);
  for (const double s : {0.0, 3.0, 10.0, 17.5}) {
    EXPECT_LT(poseGap(north.poseAtSeconds(s + lap), north.poseAtSeconds(s)), 1e-6) << s;
    EXPECT_LT(poseGap(north.poseAtSeconds(s + 3 * lap), north.poseAtSeconds(s)), 1e-6) << s;
  }
  expectSmoothAt(north, 20.0, "leaving the waypoints");
  expectSmoothAt(north, lap, "back at the start");
  expectSmoothAt(north, 20.0 + 0.5 * (lap - 20.0), "turning home");
  // On the way back it stays near the flight, at about its speed, never going on north.
  for (double s = 20.0; s <= lap; s += 0.05) {
    const Pose p = north.poseAtSeconds(s);
    ASSERT_LT(p.positionM.y, 2000.0 + 0.5 * 2000.0) << s;
    ASSERT_LT(std::abs(p.positionM.x), 2000.0) << s;
    const double speed = glm::length(north.velocityAtSeconds(s));
    ASSERT_GT(speed, 30.0) << s;
    ASSERT_LT(speed, 200.0) << s;
  }
}

TEST(ScriptedTrajectory, AClosedCircuitLoopsOnItsOwnWaypoints) {
  // A circle whose last waypoint is its first, headings given: lap = its duration.
  std::vector<Waypoint> wps;
  for (int i = 0; i <= 12; ++i) {
    const double a = 2 * std::numbers::pi * i / 12;
    wps.push_back(at(i * 3.0, 1000 * std::sin(a), 1000 * std::cos(a), 400));
    wps.back().headingRad = a + std::numbers::pi / 2;
  }
  const ScriptedTrajectory circle("circle", wps);
  EXPECT_DOUBLE_EQ(circle.lapS(), 36.0);
  EXPECT_LT(poseGap(circle.poseAtSeconds(36.0 + 4.0), circle.poseAtSeconds(4.0)), 1e-6);
  expectSmoothAt(circle, 33.0, "the last segment");
  expectSmoothAt(circle, 36.0, "the start");
  // Heading wraps the short way: it keeps turning right through north.
  EXPECT_NEAR(std::remainder(circle.poseAtSeconds(34.5).headingRad - radians(90.0 - 15.0), 2 * std::numbers::pi), 0.0,
              radians(3.0));
}

TEST(ScriptedTrajectory, HoldAndStopKeepTheLastPose) {
  for (const FlightEnd end : {FlightEnd::Hold, FlightEnd::Stop}) {
    const ScriptedTrajectory north("north", {at(0, 0, 0, 500), at(10, 0, 1000, 500)}, 0.0, end);
    EXPECT_EQ(north.end(), end);
    EXPECT_LT(poseGap(north.poseAtSeconds(25.0), north.poseAtSeconds(10.0)), 1e-12);
    EXPECT_NEAR(north.poseAtSeconds(25.0).positionM.y, 1000.0, 1e-9);
    EXPECT_EQ(glm::length(north.velocityAtSeconds(25.0)), 0.0);
  }
}

TEST(ScriptedTrajectory, NeverComesNearerTheTerrainThanItsClearance) {
  // A level pass at 300 m through a 400 m hill whose flanks rise at up to 1.14 m a metre: lifted
  // over it with 20 m to spare, climbing before it and no steeper than the lift gradient (a
  // pilot's pull-up, not the hill's own slope), untouched well away from it, without a jump.
  ScriptedTrajectory pass("pass", {at(0, 0, 0, 300), at(20, 0, 2000, 300)}, 0.0, FlightEnd::Hold, 20.0);
  auto hill = [](double, double y) { return 400.0 * std::exp(-std::pow((y - 1000.0) / 300.0, 2)); };
  pass.setTerrainFloor(hill);
  Pose previous = pass.poseAtSeconds(0.0);
  double highest = 0.0, steepest = 0.0;
  for (double s = 0.01; s <= 20.0; s += 0.01) {
    const Pose p = pass.poseAtSeconds(s);
    const double ground = hill(p.positionM.x, p.positionM.y);
    ASSERT_GE(p.positionM.z, ground + 20.0 - 1e-9) << s;
    // The cone from the top (400 − 0.3 × 650 m) and from the flanks stays under 2c below the path
    if (std::abs(p.positionM.y - 1000.0) >= 650.0) {
      ASSERT_NEAR(p.positionM.z, 300.0, 1e-9) << s;
    }
    steepest = std::max(
        steepest, std::abs(p.positionM.z - previous.positionM.z) / std::abs(p.positionM.y - previous.positionM.y));
    previous = p;
    highest = std::max(highest, p.positionM.z);
  }
  EXPECT_LE(steepest, ScriptedTrajectory::kMaxLiftGradient * 1.1);  // the smoothing's give-back adds a little
  EXPECT_GT(steepest, ScriptedTrajectory::kMaxLiftGradient * 0.8);
  EXPECT_GE(highest, 420.0);
  EXPECT_LE(highest, 430.0);  // the smoothing's allowance: at most 0.3 × 100 m/s × 0.15 s
}

// The pull-up's cone reaches as far across the ground as the terrain's relief needs, however
// slowly the flight comes: here from 200 m/s down to 20 m/s before the same hill.
TEST(ScriptedTrajectory, ASlowApproachPullsUpNoSteeperThanAFastOne) {
  ScriptedTrajectory slowing(
      "slowing",
      {at(0, 0, 0, 300), at(5, 0, 1000, 300), at(10, 0, 2000, 300), at(15, 0, 2700, 300), at(20, 0, 3100, 300),
       at(25, 0, 3350, 300), at(30, 0, 3500, 300), at(35, 0, 3600, 300), at(40, 0, 3700, 300)},
      0.0, FlightEnd::Hold, 20.0);
  auto hill = [](double, double y) { return 400.0 * std::exp(-std::pow((y - 3400.0) / 300.0, 2)); };
  slowing.setTerrainFloor(hill);
  Pose previous = slowing.poseAtSeconds(0.0);
  double steepest = 0.0;
  for (double s = 0.01; s <= 40.0; s += 0.01) {
    const Pose p = slowing.poseAtSeconds(s);
    ASSERT_GE(p.positionM.z, hill(p.positionM.x, p.positionM.y) + 20.0 - 1e-9) << s;
    ASSERT_GT(p.positionM.y, previous.positionM.y) << s;  // the track goes on north
    steepest =
        std::max(steepest, std::abs(p.positionM.z - previous.positionM.z) / (p.positionM.y - previous.positionM.y));
    previous = p;
  }
  EXPECT_LE(steepest, ScriptedTrajectory::kMaxLiftGradient * 1.1);  // the smoothing's give-back adds a little
}

// A looping flight's floor wraps round: the pull-up for a hill just after the lap's start begins
// at the end of the lap before, and a lap later the flight is where it was.
TEST(ScriptedTrajectory, ALoopingFlightsLiftWrapsRoundTheLap) {
  const ScriptedTrajectory base("circuit", {at(0, 0, 0, 300), at(10, 0, 1000, 300), at(20, 1000, 1000, 300),
                                            at(30, 1000, 0, 300), at(40, 0, 0, 300)});
  ScriptedTrajectory circuit = base;
  auto hill = [](double x, double y) {
    return 400.0 * std::exp(-(x * x + (y - 150.0) * (y - 150.0)) / (120.0 * 120.0));
  };
  circuit.setTerrainFloor(hill);
  const double lap = circuit.lapS();
  EXPECT_GT(circuit.poseAtSeconds(lap - 0.5).positionM.z, base.poseAtSeconds(lap - 0.5).positionM.z + 5.0);
  for (const double s : {0.0, 1.3, lap - 0.5, 17.0}) {
    EXPECT_NEAR(circuit.poseAtSeconds(s + lap).positionM.z, circuit.poseAtSeconds(s).positionM.z, 1e-6) << s;
  }
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

TEST(ScriptedTrajectory, AFlightFileSaysWhatHappensAtItsEnd) {
  const std::string waypoints =
      "[[waypoint]]\nt = 0\nposition = [0, 0, 300]\n[[waypoint]]\nt = 10\nposition = [0, 1000, 300]\n";
  EXPECT_EQ(ScriptedTrajectory::load(writeFlight("default_end", waypoints)).end(), FlightEnd::Loop);
  EXPECT_EQ(ScriptedTrajectory::load(writeFlight("default_end", waypoints)).clearanceM(), 15.0);
  const auto stop = ScriptedTrajectory::load(writeFlight("stop", "end = \"stop\"\nclearance_m = 40\n" + waypoints));
  EXPECT_EQ(stop.end(), FlightEnd::Stop);
  EXPECT_EQ(stop.clearanceM(), 40.0);
  EXPECT_EQ(ScriptedTrajectory::load(writeFlight("hold", "end = \"hold\"\n" + waypoints)).end(), FlightEnd::Hold);
  const auto path = writeFlight("bad_end", "end = \"straight\"\n" + waypoints);
  try {
    (void)ScriptedTrajectory::load(path);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":1: end"), std::string::npos) << e.what();
  }
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
