#pragma once
// A simple stick-driven flight model for free flight over the terrain when no host drives the
// IG: stick → roll and pitch rates, rudder → yaw rate, throttle → airspeed, coordinated turns,
// and a terrain-following floor so the eye point never goes below the ground.
//
// One thread steps it (step()); any thread asks poseAt(t), which extrapolates the newest state
// at its current rates — lock-free, so the field thread can ask at every field.

#include <motion/MotionSource.h>

#include <fieldcast/SeqLock.h>

#include <glm/vec3.hpp>

#include <functional>

namespace fieldcast::motion {

/// Pilot inputs, normalised. Roll right, pitch nose-up and yaw right are positive.
struct FlightControls {
  double roll = 0.0;      ///< −1 … 1
  double pitch = 0.0;     ///< −1 … 1
  double yaw = 0.0;       ///< −1 … 1
  double throttle = 0.5;  ///< 0 … 1
};

/// Limits and rates of the flight model.
struct FlightModelParams {
  double maxRollRateRadS = 1.5;     ///< full stick roll rate (≈ 86°/s)
  double maxPitchRateRadS = 0.5;    ///< full stick pitch rate (≈ 29°/s)
  double maxYawRateRadS = 0.25;     ///< full rudder yaw rate, added to the turn rate
  double maxBankRad = 1.3;          ///< bank limit (≈ 75°)
  double maxPitchRad = 1.2;         ///< pitch limit either way (≈ 69°)
  double minSpeedMps = 40.0;        ///< airspeed at throttle 0
  double maxSpeedMps = 300.0;       ///< airspeed at throttle 1
  double speedTimeConstantS = 3.0;  ///< first-order lag of airspeed to throttle
  double minClearanceM = 15.0;      ///< lowest eye height above the terrain
};

/// The state the model publishes after each step.
struct FlightState {
  TimePoint time{};
  Pose pose;
  double speedMps = 0.0;
  double rollRateRadS = 0.0;
  double pitchRateRadS = 0.0;
  double headingRateRadS = 0.0;
};

/// Stick-driven kinematic flight model. step() from one thread; poseAt() from any.
class FlightModel final : public MotionSource {
 public:
  /// Terrain height (metres) at world (x, y); used for the clearance floor. May be empty.
  using TerrainHeightFn = std::function<double(double xM, double yM)>;

  FlightModel(const FlightModelParams& params, const Pose& start, double startSpeedMps, TimePoint startTime,
              TerrainHeightFn terrainHeight = {});

  /// Integrates from the last step to `now` with `controls` held over the interval (sub-stepped
  /// at most 5 ms at a time). Ignores a `now` earlier than the last step. Owner thread only.
  void step(TimePoint now, const FlightControls& controls);

  /// Starts over at `pose` and `speedMps` at `time` (rates zero), as if just constructed: the
  /// cockpit's reset. Owner thread only; RT-safe (no allocation).
  void reset(const Pose& pose, double speedMps, TimePoint time) noexcept;

  /// The newest state. Any thread, RT-safe.
  FlightState state() const noexcept { return mState.load(); }

  /// Pose at `t`, extrapolated from the newest state at its current rates (a constant-rate turn),
  /// so a field a few milliseconds ahead of the last step is predicted rather than held. RT-safe.
  Pose poseAt(TimePoint t) const noexcept override;

 private:
  void integrate(FlightState& s, double dtS, const FlightControls& c) const;

  FlightModelParams mParams;
  TerrainHeightFn mTerrainHeight;
  FlightState mWorking;  // owner thread's copy
  SeqLock<FlightState> mState;
};

}  // namespace fieldcast::motion
