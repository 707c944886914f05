#include <motion/FlightModel.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fieldcast::motion {
namespace {

constexpr double kGravityMps2 = 9.80665;
constexpr double kMaxSubstepS = 0.005;

double wrapAngle(double a) noexcept { return std::remainder(a, 2.0 * std::numbers::pi); }

glm::dvec3 velocityOf(const FlightState& s) noexcept {
  const double ch = std::cos(s.pose.headingRad), sh = std::sin(s.pose.headingRad);
  const double cp = std::cos(s.pose.pitchRad), sp = std::sin(s.pose.pitchRad);
  return s.speedMps * glm::dvec3{sh * cp, ch * cp, sp};
}

}  // namespace

FlightModel::FlightModel(const FlightModelParams& params, const Pose& start, double startSpeedMps, TimePoint startTime,
                         TerrainHeightFn terrainHeight)
    : mParams(params), mTerrainHeight(std::move(terrainHeight)) {
  reset(start, startSpeedMps, startTime);
}

void FlightModel::reset(const Pose& pose, double speedMps, TimePoint time) noexcept {
  mWorking = FlightState{};
  mWorking.time = time;
  mWorking.pose = pose;
  mWorking.speedMps = speedMps;
  mState.store(mWorking);
}

void FlightModel::integrate(FlightState& s, double dt, const FlightControls& c) const {
  const auto clamp1 = [](double v) { return std::clamp(v, -1.0, 1.0); };
  // Rates from the stick; a limit stops the rate, it does not bounce.
  s.rollRateRadS = clamp1(c.roll) * mParams.maxRollRateRadS;
  s.pitchRateRadS = clamp1(c.pitch) * mParams.maxPitchRateRadS;
  s.pose.rollRad = std::clamp(s.pose.rollRad + s.rollRateRadS * dt, -mParams.maxBankRad, mParams.maxBankRad);
  s.pose.pitchRad = std::clamp(s.pose.pitchRad + s.pitchRateRadS * dt, -mParams.maxPitchRad, mParams.maxPitchRad);
  if (std::abs(s.pose.rollRad) >= mParams.maxBankRad) s.rollRateRadS = 0.0;
  if (std::abs(s.pose.pitchRad) >= mParams.maxPitchRad) s.pitchRateRadS = 0.0;

  // Coordinated turn: bank makes the heading turn at g·tan φ / V; the rudder adds a little.
  const double speed = std::max(s.speedMps, 1.0);
  s.headingRateRadS = kGravityMps2 * std::tan(s.pose.rollRad) / speed + clamp1(c.yaw) * mParams.maxYawRateRadS;
  s.pose.headingRad = wrapAngle(s.pose.headingRad + s.headingRateRadS * dt);

  // Airspeed follows the throttle with a first-order lag.
  const double target =
      mParams.minSpeedMps + std::clamp(c.throttle, 0.0, 1.0) * (mParams.maxSpeedMps - mParams.minSpeedMps);
  s.speedMps += (target - s.speedMps) * (1.0 - std::exp(-dt / mParams.speedTimeConstantS));

  s.pose.positionM += velocityOf(s) * dt;

  // Terrain floor: never below the clearance; a dive into the ground levels out.
  if (mTerrainHeight) {
    const double floor = mTerrainHeight(s.pose.positionM.x, s.pose.positionM.y) + mParams.minClearanceM;
    if (s.pose.positionM.z < floor) {
      s.pose.positionM.z = floor;
      if (s.pose.pitchRad < 0.0) {
        s.pose.pitchRad = 0.0;
        s.pitchRateRadS = 0.0;
      }
    }
  }
}

void FlightModel::step(TimePoint now, const FlightControls& controls) {
  double remaining = toSeconds(now - mWorking.time);
  if (remaining <= 0.0) return;
  while (remaining > 0.0) {
    const double dt = std::min(remaining, kMaxSubstepS);
    integrate(mWorking, dt, controls);
    remaining -= dt;
  }
  mWorking.time = now;
  mState.store(mWorking);
}

Pose FlightModel::poseAt(TimePoint t) const noexcept {
  const FlightState s = mState.load();
  const double dt = toSeconds(t - s.time);
  Pose p = s.pose;
  p.positionM += velocityOf(s) * dt;
  p.headingRad = wrapAngle(p.headingRad + s.headingRateRadS * dt);
  p.pitchRad = std::clamp(p.pitchRad + s.pitchRateRadS * dt, -mParams.maxPitchRad, mParams.maxPitchRad);
  p.rollRad = std::clamp(p.rollRad + s.rollRateRadS * dt, -mParams.maxBankRad, mParams.maxBankRad);
  return p;
}

}  // namespace fieldcast::motion
