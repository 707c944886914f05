#pragma once
// Camera/vehicle pose in world coordinates (DESIGN.md §6): x east, y north, z up, metres;
// attitude as heading, pitch, roll applied in that order. Conventions.h turns it into axes.

#include <glm/vec3.hpp>

#include <numbers>

namespace fieldcast {

/// A position and attitude. Angles in radians:
/// heading clockwise from north (0 looks north, π/2 looks east), pitch nose-up positive,
/// roll right-wing-down positive.
struct Pose {
  glm::dvec3 positionM{0.0, 0.0, 0.0};  ///< world metres: x east, y north, z up
  double headingRad = 0.0;
  double pitchRad = 0.0;
  double rollRad = 0.0;

  friend bool operator==(const Pose&, const Pose&) = default;
};

/// Degrees to radians.
constexpr double radians(double degrees) noexcept { return degrees * std::numbers::pi / 180.0; }
/// Radians to degrees.
constexpr double degrees(double radiansValue) noexcept { return radiansValue * 180.0 / std::numbers::pi; }

}  // namespace fieldcast
