#pragma once
// A scripted flight: timed waypoints joined by C² splines in position and attitude. It drives the
// demo and the warp-quality evaluation, where it is also the ground truth for every field.
// File format: config/README.md, "Flight files".

#include <motion/CubicSpline.h>
#include <motion/MotionSource.h>

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <functional>
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

/// What a flight does after its last waypoint.
enum class FlightEnd : std::uint8_t {
  Loop,  ///< fly back to the first waypoint and round again (a closed circuit loops on its own waypoints)
  Hold,  ///< hold the last waypoint's pose
  Stop,  ///< hold the last pose; the service ends the run there
};

/// A pose trajectory through waypoints. Position: a natural cubic spline per axis over time.
/// Attitude, per angle, either a spline through the waypoints' values (heading unwrapped, so it
/// turns the short way) or, when no waypoint gives that angle, derived from the path: heading
/// along the ground track, pitch along the climb angle plus `cameraPitchOffsetRad`, roll as a
/// coordinated turn tan φ = V·ψ̇ / g. After the last waypoint the flight does what `end` says;
/// before the first it goes straight. With a terrain floor set, the eye never comes nearer the
/// terrain than the flight's clearance.
class ScriptedTrajectory final : public MotionSource {
 public:
  /// Terrain height (metres) at world (x, y), for the clearance floor. Must be RT-safe.
  using TerrainHeightFn = std::function<double(double xM, double yM)>;

  /// Builds the splines. Throws std::invalid_argument (naming the waypoint) unless there are ≥ 2
  /// waypoints, times strictly increase, and each angle is given on every waypoint or on none.
  /// A looping flight whose last waypoint is within 1 m of its first is a closed circuit (its last
  /// segment is flown as a leg that joins the first one smoothly); any other turns round and flies
  /// back to its first waypoint in a leg at about its mean speed. Each leg is C² with the splines.
  ScriptedTrajectory(std::string name, std::vector<Waypoint> waypoints, double cameraPitchOffsetRad = 0.0,
                     FlightEnd end = FlightEnd::Loop, double clearanceM = 15.0);

  /// Reads a flight file (config/flights/*.toml). Throws ConfigError (a std::runtime_error)
  /// naming the file, the line and the key on any problem.
  static ScriptedTrajectory load(const std::string& path);

  /// Instant of the flight's time 0 (default: TimePoint{} — set it when the flight starts).
  void setStartTime(TimePoint start) noexcept { mStart = start; }
  TimePoint startTime() const noexcept { return mStart; }

  /// Pose at instant `t`. Thread-safe, RT-safe.
  Pose poseAt(TimePoint t) const noexcept override;
  /// Keeps the eye at least clearanceM() above `terrainHeight`, as a pilot would: the position is
  /// lifted smoothly where the path comes within 2 × clearance of the *lift floor* — the terrain
  /// under the path raised to a slope of kMaxLiftGradient (rise over horizontal distance) on either
  /// side of every point and smoothed — so a flight climbs over a ridge before it and no steeper
  /// than about that gradient, rather than with the terrain's own slopes. The attitude still
  /// follows the path. Samples the flight once (every kLiftStepS over a lap, or to the end) and
  /// compares each sample with those within relief / gradient of it; set before the flight is
  /// shared between threads; empty: no floor.
  void setTerrainFloor(TerrainHeightFn terrainHeight);
  /// The lift floor's slope: rise per metre of horizontal distance (about 17°).
  static constexpr double kMaxLiftGradient = 0.3;
  /// How often the lift floor is sampled along the flight, seconds.
  static constexpr double kLiftStepS = 0.05;

  /// Pose at `seconds` after the start. RT-safe.
  Pose poseAtSeconds(double seconds) const noexcept;
  /// World velocity (m/s) at `seconds` after the start. RT-safe.
  glm::dvec3 velocityAtSeconds(double seconds) const noexcept;

  const std::string& name() const noexcept { return mName; }
  /// Time of the last waypoint, seconds.
  double durationS() const noexcept { return mDurationS; }
  FlightEnd end() const noexcept { return mEnd; }
  /// Lowest eye height above the terrain floor, metres.
  double clearanceM() const noexcept { return mClearanceM; }
  /// Seconds of one lap of a looping flight (waypoints plus the leg back); the duration otherwise.
  double lapS() const noexcept { return mLapS; }

 private:
  /// A quintic Hermite curve over [0, h]: value, slope and curvature given at both ends.
  struct Quintic {
    double p0 = 0, v0 = 0, a0 = 0, p1 = 0, v1 = 0, a1 = 0, h = 1;
    SplineSample at(double t) const noexcept;
  };
  /// One piece of the leg back to the start: x, y, z over `durationS`.
  struct LegPiece {
    double durationS = 0.0;
    std::array<Quintic, 3> axis;
  };
  void buildLoopLeg(const std::vector<Waypoint>& waypoints);
  /// Position and angle samples at `seconds` after the start (after the end rule).
  struct Samples {
    SplineSample x, y, z;
    std::optional<SplineSample> heading, pitch, roll;
  };
  Samples samplesAt(double seconds) const noexcept;
  /// The lift floor at `seconds` (setTerrainFloor), never below `groundM`, the terrain under the
  /// eye there.
  double liftFloorM(double seconds, double groundM) const noexcept;

  std::string mName;
  double mDurationS = 0.0;
  double mFirstS = 0.0;  // time of the first waypoint
  double mJoinS = 0.0;   // a loop leaves the splines here for the leg back
  double mLapS = 0.0;
  std::vector<LegPiece> mLeg;                        // a loop's leg back to the first waypoint
  std::array<std::optional<Quintic>, 3> mLegAngles;  // heading, pitch, roll over the whole leg
  double mCameraPitchOffsetRad = 0.0;
  FlightEnd mEnd = FlightEnd::Loop;
  double mClearanceM = 15.0;
  TerrainHeightFn mTerrainHeight;
  std::vector<double> mLiftFloorM;  // every mLiftStepS from the first waypoint (setTerrainFloor)
  double mLiftStepS = kLiftStepS;
  TimePoint mStart{};
  CubicSpline mX, mY, mZ;
  std::optional<CubicSpline> mHeading, mPitch, mRoll;  // absent: follow the flight path
};

}  // namespace fieldcast::motion
