// Flight files with scripted entities: each entity's model path is resolved against the file, its
// waypoints become its own trajectory on the flight's clock, and mistakes are named by line and key.
#include <motion/FlightFile.h>

#include <fieldcast/Conventions.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace fieldcast::motion {
namespace {

std::filesystem::path writeFlight(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "fieldcast_flight_files";
  std::filesystem::create_directories(dir);
  const auto path = dir / (name + ".toml");
  std::ofstream(path) << text;
  return path;
}

const std::string kOwnship = R"(name = "with traffic"
[[waypoint]]
t = 0
position = [0, 0, 300]
[[waypoint]]
t = 10
position = [0, 1000, 300]
)";

TEST(FlightFile, ScriptedEntitiesFollowTheirOwnWaypoints) {
  const auto path = writeFlight("entities", kOwnship + R"(
[[entity]]
name = "van"
model = "../models/van.vox"
on_ground = true
end = "hold"
[[entity.waypoint]]
t = 0
position = [100, 0, 0]
[[entity.waypoint]]
t = 20
position = [100, 400, 0]

[[entity]]
model = "/abs/plane.vox"
scale = 2
[[entity.waypoint]]
t = 0
position = [-500, 300, 400]
[[entity.waypoint]]
t = 10
position = [500, 300, 400]
)");
  const FlightFile file = readFlightFile(path);
  EXPECT_EQ(file.ownship.name(), "with traffic");
  ASSERT_EQ(file.entities.size(), 2u);
  const ScriptedEntity& van = file.entities[0];
  EXPECT_EQ(van.name, "van");
  EXPECT_EQ(van.model, path.parent_path() / "../models/van.vox");
  EXPECT_TRUE(van.onGround);
  EXPECT_EQ(van.scale, 1.0);
  EXPECT_EQ(van.path.end(), FlightEnd::Hold);
  EXPECT_NEAR(van.path.poseAtSeconds(10.0).positionM.y, 200.0, 1e-9);
  EXPECT_NEAR(van.path.poseAtSeconds(10.0).headingRad, 0.0, 1e-9);  // along its track, north
  const ScriptedEntity& plane = file.entities[1];
  EXPECT_EQ(plane.name, "entity 2");
  EXPECT_EQ(plane.model, "/abs/plane.vox");
  EXPECT_EQ(plane.scale, 2.0);
  EXPECT_FALSE(plane.onGround);
  EXPECT_NEAR(plane.path.poseAtSeconds(5.0).headingRad, radians(90.0), 1e-9);  // east
  EXPECT_NEAR(plane.path.poseAtSeconds(5.0).positionM.z, 400.0, 1e-9);         // no clearance floor
}

TEST(FlightFile, EntityMistakesAreNamedByLineAndKey) {
  const auto expectError = [](const std::string& name, const std::string& text, const std::string& message) {
    const auto path = writeFlight(name, kOwnship + text);
    try {
      (void)readFlightFile(path);
      ADD_FAILURE() << "no error for " << name;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  expectError("no_model", "[[entity]]\n[[entity.waypoint]]\nt = 0\nposition = [0, 0, 0]\n",
              "entity[1].model: an entity needs a model");
  expectError("one_waypoint", "[[entity]]\nmodel = \"v.vox\"\n[[entity.waypoint]]\nt = 0\nposition = [0, 0, 0]\n",
              "expected at least two [[entity.waypoint]] tables");
  expectError("scale", "[[entity]]\nmodel = \"v.vox\"\nscale = 9\n",
              "entity[1].scale: expected a number from 0.25 to 4, got 9");
  expectError("backwards",
              "[[entity]]\nname = \"bus\"\nmodel = \"v.vox\"\n[[entity.waypoint]]\nt = 5\nposition = [0, 0, 0]\n"
              "[[entity.waypoint]]\nt = 1\nposition = [9, 0, 0]\n",
              "entity 'bus': trajectory: waypoint 2");
  expectError("unknown",
              "[[entity]]\nmodel = \"v.vox\"\nspeed = 3\n[[entity.waypoint]]\nt = 0\nposition = [0, 0, 0]\n"
              "[[entity.waypoint]]\nt = 1\nposition = [9, 0, 0]\n",
              "entity[1].speed");
}

}  // namespace
}  // namespace fieldcast::motion
