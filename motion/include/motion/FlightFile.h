#pragma once
// A flight file (config/README.md, "Flight files"): the ownship's scripted flight and the
// scripted entities that move in the scene with it (a vehicle on a road, an aircraft crossing).

#include <motion/ScriptedTrajectory.h>

#include <filesystem>
#include <string>
#include <vector>

namespace fieldcast::motion {

/// An entity scripted by a flight file: a voxel model moved along its own waypoints, on the
/// flight's clock.
struct ScriptedEntity {
  std::string name;
  std::filesystem::path model;  ///< a .vox file (relative paths resolved against the flight file)
  double scale = 1.0;
  /// Keeps to the ground: its height is the terrain's under it (the waypoints' z are ignored),
  /// level, heading along its track. Otherwise it flies its waypoints, banking into its turns.
  bool onGround = false;
  ScriptedTrajectory path;
};

struct FlightFile {
  ScriptedTrajectory ownship;
  std::vector<ScriptedEntity> entities;
};

/// Reads a flight file. Throws ConfigError (a std::runtime_error) naming the file, the line and
/// the key on any problem.
FlightFile readFlightFile(const std::filesystem::path& path);

}  // namespace fieldcast::motion
