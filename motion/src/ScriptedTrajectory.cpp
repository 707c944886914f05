#include <motion/ScriptedTrajectory.h>

#include <toml++/toml.h>

#include <cmath>
#include <numbers>
#include <sstream>
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
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << path << ':' << e.source().begin.line << ": " << e.description();
    throw std::runtime_error(s.str());
  }
  auto fail = [&](const toml::node& node, const std::string& key, const std::string& what) {
    throw std::runtime_error(path + ":" + std::to_string(node.source().begin.line) + ": " + key + ": " + what);
  };
  for (const auto& [key, node] : root) {
    const std::string k(key.str());
    if (k != "name" && k != "description" && k != "camera_pitch_deg" && k != "waypoint") {
      fail(node, k, "unknown key (expected name, description, camera_pitch_deg, waypoint)");
    }
  }
  const std::string name = root["name"].value_or(std::string("unnamed flight"));
  double cameraPitchDeg = 0.0;
  if (const toml::node* n = root.get("camera_pitch_deg")) {
    const auto v = n->value<double>();
    if (!v || *v < -90.0 || *v > 90.0) fail(*n, "camera_pitch_deg", "expected degrees from -90 to 90");
    cameraPitchDeg = *v;
  }
  const toml::array* list = root["waypoint"].as_array();
  if (!list || list->size() < 2) {
    throw std::runtime_error(path + ": waypoint: expected at least two [[waypoint]] tables");
  }
  std::vector<Waypoint> waypoints;
  for (std::size_t i = 0; i < list->size(); ++i) {
    const toml::table* wt = (*list)[i].as_table();
    const std::string prefix = "waypoint[" + std::to_string(i + 1) + "].";
    if (!wt) fail((*list)[i], prefix, "expected a table");
    Waypoint w;
    for (const auto& [key, node] : *wt) {
      const std::string k(key.str());
      if (k == "t") {
        const auto v = node.value<double>();
        if (!v || !std::isfinite(*v)) fail(node, prefix + k, "expected seconds");
        w.timeS = *v;
      } else if (k == "position") {
        const toml::array* p = node.as_array();
        if (!p || p->size() != 3) fail(node, prefix + k, "expected [x, y, z] in metres");
        for (int a = 0; a < 3; ++a) {
          const auto v = (*p)[static_cast<std::size_t>(a)].value<double>();
          if (!v || !std::isfinite(*v)) fail(node, prefix + k, "expected [x, y, z] in metres");
          w.positionM[a] = *v;
        }
      } else if (k == "heading_deg" || k == "pitch_deg" || k == "roll_deg") {
        const auto v = node.value<double>();
        if (!v || !std::isfinite(*v)) fail(node, prefix + k, "expected degrees");
        const double rad = radians(*v);
        (k == "heading_deg" ? w.headingRad : k == "pitch_deg" ? w.pitchRad : w.rollRad) = rad;
      } else {
        fail(node, prefix + k, "unknown key (expected t, position, heading_deg, pitch_deg, roll_deg)");
      }
    }
    if (!wt->contains("t") || !wt->contains("position")) fail(*wt, prefix, "t and position are required");
    waypoints.push_back(w);
  }
  try {
    return ScriptedTrajectory(name, std::move(waypoints), radians(cameraPitchDeg));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace fieldcast::motion
