#pragma once
// The [motion] section of the service configuration (keys in config/README.md): what moves the
// eye point — a scripted flight, the stick's flight model or a CIGI host — and how long the run lasts.

#include <fieldcast/ConfigReader.h>
#include <fieldcast/Pose.h>

#include <cstdint>
#include <filesystem>

namespace fieldcast::motion {

/// Where the ownship's pose comes from.
enum class MotionKind : std::uint8_t { Flight, Stick, Host };

/// What [motion] sets.
struct MotionConfig {
  MotionKind source = MotionKind::Flight;
  std::filesystem::path flightPath;              ///< scripted flight (source = "flight")
  Pose start{{0.0, 0.0, 500.0}, 0.0, 0.0, 0.0};  ///< where the stick's flight model starts
  double startSpeedMps = 120.0;
  double durationS = 0.0;  ///< stop after this long; 0 = until a signal
};

/// Reads [motion] (source, flight, start, start_speed_mps, duration_s). Throws ConfigError.
MotionConfig readMotionConfig(ConfigReader& table);

}  // namespace fieldcast::motion
