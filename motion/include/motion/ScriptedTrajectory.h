#pragma once
// A scripted flight: timed waypoints joined by C² splines in position and attitude. It drives the
// demo and the warp-quality evaluation, where it is also the ground truth for every field.
// File format: config/flights/README.md.

#include <motion/CubicSpline.h>
#include <motion/MotionSource.h>

#include <glm/vec3.hpp>

#include <optional>
#include <string>
#include <vector>

namespace fieldcast::motion {

/// One timed waypoint. Angles in radians; when absent they follow the flight path (see below).
struct Waypoint {
  double timeS = 0.0;         ///< seconds from the start of the flight
  glm::dvec3 positionM{0.0};  ///< world metres (x east, y north, z up)
  std::optional<double> headingRad;
  std::optional<double> pitchRad;
  std::optional<double> rollRad;
};

/// A pose trajectory through waypoints. Position: a natural cubic spline per axis over time.
/// Attitude, per angle, either a spline through the waypoints' values (heading unwrapped, so it
/// turns the short way) or, when no waypoint gives that angle, derived from the path: heading
/// along the ground track, pitch along the climb angle plus `cameraPitchOffsetRad`, roll as a
/// coordinated turn tan φ = V·ψ̇ / g. Beyond the last waypoint the flight goes on straight.
class ScriptedTrajectory final : public MotionSource {
 public:
  /// Builds the splines. Throws std::invalid_argument (naming the waypoint) unless there are ≥ 2
  /// waypoints, times strictly increase, and each angle is given on every waypoint or on none.
  ScriptedTrajectory(std::string name, std::vector<Waypoint> waypoints, double cameraPitchOffsetRad = 0.0);

  /// Reads a flight file (config/flights/*.toml). Throws ConfigError (a std::runtime_error)
  /// naming the file, the line and the key on any problem.
  static ScriptedTrajectory load(const std::string& path);

  /// Instant of the flight's time 0 (default: TimePoint{} — set it when the flight starts).
  void setStartTime(TimePoint start) noexcept { mStart = start; }
  TimePoint startTime() const noexcept { return mStart; }

  /// Pose at instant `t`. Thread-safe, RT-safe.
  Pose poseAt(TimePoint t) const noexcept override;
  /// Pose at `seconds` after the start. RT-safe.
  Pose poseAtSeconds(double seconds) const noexcept;
  /// World velocity (m/s) at `seconds` after the start. RT-safe.
  glm::dvec3 velocityAtSeconds(double seconds) const noexcept;

  const std::string& name() const noexcept { return mName; }
  /// Time of the last waypoint, seconds.
  double durationS() const noexcept { return mDurationS; }

 private:
  std::string mName;
  double mDurationS = 0.0;
  double mCameraPitchOffsetRad = 0.0;
  TimePoint mStart{};
  CubicSpline mX, mY, mZ;
  std::optional<CubicSpline> mHeading, mPitch, mRoll;  // absent: follow the flight path
};

}  // namespace fieldcast::motion
