#include <motion/ScriptedTrajectory.h>

#include <fieldcast/ConfigReader.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace fieldcast::motion {
namespace {

constexpr double kGravityMps2 = 9.80665;

// Spline through one optional angle of every waypoint, or nothing when no waypoint has it.
std::optional<CubicSpline> angleSpline(const std::vector<Waypoint>& wps, std::optional<double> Waypoint::*angle,
                                       const char* name, bool unwrap) {
  std::size_t given = 0;
  for (const auto& w : wps) given += (w.*angle).has_value() ? 1 : 0;
  if (given == 0) return std::nullopt;
  if (given != wps.size()) {
    throw std::invalid_argument(std::string("trajectory: ") + name + " must be given on every waypoint or on none (" +
                                std::to_string(given) + " of " + std::to_string(wps.size()) + " have it)");
  }
  std::vector<double> t, v;
  for (const auto& w : wps) {
    double a = *(w.*angle);
    // Unwrap so consecutive headings differ by at most π: 350° → 10° turns right by 20°.
    if (unwrap && !v.empty()) a = v.back() + std::remainder(a - v.back(), 2.0 * std::numbers::pi);
    t.push_back(w.timeS);
    v.push_back(a);
  }
  return CubicSpline(std::move(t), std::move(v));
}

CubicSpline axisSpline(const std::vector<Waypoint>& wps, int axis) {
  std::vector<double> t, v;
  for (const auto& w : wps) {
    t.push_back(w.timeS);
    v.push_back(w.positionM[axis]);
  }
  return CubicSpline(std::move(t), std::move(v));
}

}  // namespace

ScriptedTrajectory::ScriptedTrajectory(std::string name, std::vector<Waypoint> waypoints, double cameraPitchOffsetRad)
    : mName(std::move(name)), mCameraPitchOffsetRad(cameraPitchOffsetRad) {
  if (waypoints.size() < 2) throw std::invalid_argument("trajectory: need at least 2 waypoints");
  for (std::size_t i = 1; i < waypoints.size(); ++i) {
    if (!(waypoints[i].timeS > waypoints[i - 1].timeS)) {
      throw std::invalid_argument("trajectory: waypoint " + std::to_string(i + 1) + ": t must be later than waypoint " +
                                  std::to_string(i) + "'s");
    }
  }
  mDurationS = waypoints.back().timeS;
  mX = axisSpline(waypoints, 0);
  mY = axisSpline(waypoints, 1);
  mZ = axisSpline(waypoints, 2);
  mHeading = angleSpline(waypoints, &Waypoint::headingRad, "heading", true);
  mPitch = angleSpline(waypoints, &Waypoint::pitchRad, "pitch", false);
  mRoll = angleSpline(waypoints, &Waypoint::rollRad, "roll", false);
}

glm::dvec3 ScriptedTrajectory::velocityAtSeconds(double s) const noexcept {
  return {mX.sample(s).slope, mY.sample(s).slope, mZ.sample(s).slope};
}

Pose ScriptedTrajectory::poseAtSeconds(double s) const noexcept {
  const SplineSample x = mX.sample(s), y = mY.sample(s), z = mZ.sample(s);
  Pose pose;
  pose.positionM = {x.value, y.value, z.value};

  const double groundSpeed2 = x.slope * x.slope + y.slope * y.slope;
  const double groundSpeed = std::sqrt(groundSpeed2);
  // Heading clockwise from north along the ground track; its rate from the turning of the track.
  pose.headingRad = mHeading ? mHeading->sample(s).value : std::atan2(x.slope, y.slope);
  pose.pitchRad = mPitch ? mPitch->sample(s).value : std::atan2(z.slope, groundSpeed) + mCameraPitchOffsetRad;
  if (mRoll) {
    pose.rollRad = mRoll->sample(s).value;
  } else if (groundSpeed2 > 1e-6) {
    const double headingRate = (y.slope * x.curvature - x.slope * y.curvature) / groundSpeed2;
    pose.rollRad = std::atan(groundSpeed * headingRate / kGravityMps2);
  }
  return pose;
}

Pose ScriptedTrajectory::poseAt(TimePoint t) const noexcept { return poseAtSeconds(toSeconds(t - mStart)); }

ScriptedTrajectory ScriptedTrajectory::load(const std::string& path) {
  ConfigReader root = ConfigDocument::parseFile(path).root();
  const std::string name = root.nonEmptyString("name", "unnamed flight");
  root.string("description", "");
  const double cameraPitchDeg = root.number("camera_pitch_deg", 0.0, -90.0, 90.0);
  std::vector<ConfigReader> tables = root.tables("waypoint");
  if (tables.size() < 2) root.fail("waypoint", "expected at least two [[waypoint]] tables");
  root.finish();
  std::vector<Waypoint> waypoints;
  constexpr double kMaxAbs = 1e9;  // any finite value a flight file could mean
  for (ConfigReader& t : tables) {
    Waypoint w;
    if (!t.has("t") || !t.has("position")) t.fail("t", "t and position are required");
    w.timeS = t.number("t", 0.0, -kMaxAbs, kMaxAbs);
    const std::vector<double> p = t.numbers("position", {}, 3);
    w.positionM = {p[0], p[1], p[2]};
    // An angle left out follows the flight path (see ScriptedTrajectory.h).
    if (t.has("heading_deg")) w.headingRad = radians(t.number("heading_deg", 0.0, -kMaxAbs, kMaxAbs));
    if (t.has("pitch_deg")) w.pitchRad = radians(t.number("pitch_deg", 0.0, -kMaxAbs, kMaxAbs));
    if (t.has("roll_deg")) w.rollRad = radians(t.number("roll_deg", 0.0, -kMaxAbs, kMaxAbs));
    t.finish();
    waypoints.push_back(w);
  }
  try {
    return ScriptedTrajectory(name, std::move(waypoints), radians(cameraPitchDeg));
  } catch (const std::invalid_argument& e) {
    throw ConfigError(path + ": " + e.what());
  }
}

}  // namespace fieldcast::motion
