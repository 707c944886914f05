#include <motion/ScriptedTrajectory.h>

#include <motion/FlightFile.h>

#include <fieldcast/ConfigReader.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
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

ScriptedTrajectory::ScriptedTrajectory(std::string name, std::vector<Waypoint> waypoints, double cameraPitchOffsetRad,
                                       FlightEnd end, double clearanceM)
    : mName(std::move(name)), mCameraPitchOffsetRad(cameraPitchOffsetRad), mEnd(end), mClearanceM(clearanceM) {
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
  mFirstS = waypoints.front().timeS;
  mJoinS = mLapS = mDurationS;
  if (end == FlightEnd::Loop) buildLoopLeg(waypoints);
}

// The quintic Hermite basis (value, slope, curvature at both ends) and its two derivatives.
SplineSample ScriptedTrajectory::Quintic::at(double t) const noexcept {
  const double u = std::clamp(t / h, 0.0, 1.0);
  const double u2 = u * u, u3 = u2 * u, u4 = u3 * u, u5 = u4 * u;
  // Basis functions for p0, h·v0, h²·a0, h²·a1, h·v1, p1; then d/du and d²/du².
  const double b[6] = {
      1 - 10 * u3 + 15 * u4 - 6 * u5, u - 6 * u3 + 8 * u4 - 3 * u5, 0.5 * u2 - 1.5 * u3 + 1.5 * u4 - 0.5 * u5,
      0.5 * u3 - u4 + 0.5 * u5,       -4 * u3 + 7 * u4 - 3 * u5,    10 * u3 - 15 * u4 + 6 * u5};
  const double d[6] = {-30 * u2 + 60 * u3 - 30 * u4, 1 - 18 * u2 + 32 * u3 - 15 * u4, u - 4.5 * u2 + 6 * u3 - 2.5 * u4,
                       1.5 * u2 - 4 * u3 + 2.5 * u4, -12 * u2 + 28 * u3 - 15 * u4,    30 * u2 - 60 * u3 + 30 * u4};
  const double dd[6] = {-60 * u + 180 * u2 - 120 * u3, -36 * u + 96 * u2 - 60 * u3, 1 - 9 * u + 18 * u2 - 10 * u3,
                        3 * u - 12 * u2 + 10 * u3,     -24 * u + 84 * u2 - 60 * u3, 60 * u - 180 * u2 + 120 * u3};
  const double c[6] = {p0, h * v0, h * h * a0, h * h * a1, h * v1, p1};
  SplineSample out;
  for (int i = 0; i < 6; ++i) {
    out.value += b[i] * c[i];
    out.slope += d[i] * c[i];
    out.curvature += dd[i] * c[i];
  }
  out.slope /= h;
  out.curvature /= h * h;
  return out;
}

// The leg of a looping flight from where it leaves the splines back to the first waypoint. A
// closed circuit flies its last segment as the leg. Any other flight turns round: to a point
// beside the middle of the way back (to the right of its last track), heading home, then on to
// the first waypoint, at about the flight's mean speed. Slopes and curvatures match the splines
// at both ends, so the loop is C² all round.
void ScriptedTrajectory::buildLoopLeg(const std::vector<Waypoint>& wps) {
  const CubicSpline* axes[3] = {&mX, &mY, &mZ};
  auto stateAt = [&](double s, int axis) { return axes[axis]->sample(s); };
  const Waypoint& first = wps.front();
  const Waypoint& last = wps.back();
  const bool closed = glm::length(last.positionM - first.positionM) < 1.0;
  auto quintic = [](const SplineSample& a, const SplineSample& b, double h) {
    return Quintic{a.value, a.slope, a.curvature, b.value, b.slope, b.curvature, h};
  };
  double legS = 0.0;
  if (closed) {
    mJoinS = wps[wps.size() - 2].timeS;
    legS = last.timeS - mJoinS;
    LegPiece piece{legS, {}};
    for (int a = 0; a < 3; ++a)
      piece.axis[static_cast<std::size_t>(a)] = quintic(stateAt(mJoinS, a), stateAt(mFirstS, a), legS);
    mLeg.push_back(piece);
  } else {
    double pathM = 0.0;
    for (std::size_t i = 1; i < wps.size(); ++i) pathM += glm::length(wps[i].positionM - wps[i - 1].positionM);
    const double speedMps = std::max(1.0, pathM / (last.timeS - mFirstS));
    mJoinS = last.timeS;
    const glm::dvec3 home = first.positionM - last.positionM;
    const glm::dvec2 homeDir =
        glm::length(glm::dvec2(home)) > 1e-9 ? glm::normalize(glm::dvec2(home)) : glm::dvec2(0, -1);
    const glm::dvec2 track{stateAt(mJoinS, 0).slope, stateAt(mJoinS, 1).slope};
    const glm::dvec2 trackDir = glm::length(track) > 1e-9 ? glm::normalize(track) : -homeDir;
    const glm::dvec2 right{trackDir.y, -trackDir.x};
    const double asideM = std::max(500.0, 0.5 * glm::length(home));
    const glm::dvec3 middle = 0.5 * (first.positionM + last.positionM) + glm::dvec3(asideM * right, 0.0);
    // Each half: a half turn of diameter `asideM` and half the way home.
    const double halfS = (0.5 * std::numbers::pi * asideM + 0.5 * glm::length(home)) / speedMps;
    const glm::dvec3 middleVelocity{speedMps * homeDir, 0.0};
    LegPiece out{halfS, {}}, back{halfS, {}};
    for (int a = 0; a < 3; ++a) {
      const auto i = static_cast<std::size_t>(a);
      const SplineSample turn{middle[a], middleVelocity[a], 0.0};
      out.axis[i] = quintic(stateAt(mJoinS, a), turn, halfS);
      back.axis[i] = quintic(turn, stateAt(mFirstS, a), halfS);
    }
    mLeg = {out, back};
    legS = 2.0 * halfS;
  }
  // Given angles blend over the whole leg, the heading the short way round.
  const std::optional<CubicSpline>* angles[3] = {&mHeading, &mPitch, &mRoll};
  for (std::size_t a = 0; a < 3; ++a) {
    if (!*angles[a]) continue;
    const SplineSample from = (*angles[a])->sample(mJoinS);
    SplineSample to = (*angles[a])->sample(mFirstS);
    if (a == 0) to.value = from.value + std::remainder(to.value - from.value, 2.0 * std::numbers::pi);
    mLegAngles[a] = quintic(from, to, legS);
  }
  mLapS = (mJoinS - mFirstS) + legS;
}

ScriptedTrajectory::Samples ScriptedTrajectory::samplesAt(double seconds) const noexcept {
  double s = seconds;
  double legT = -1.0;  // time into the leg back, when there
  if (mEnd != FlightEnd::Loop) {
    s = std::min(s, mDurationS);
  } else if (s > mJoinS) {
    const double intoLap = std::fmod(s - mFirstS, mLapS);
    if (intoLap <= mJoinS - mFirstS) {
      s = mFirstS + intoLap;
    } else {
      legT = intoLap - (mJoinS - mFirstS);
    }
  }
  Samples out;
  if (legT < 0.0) {
    out.x = mX.sample(s);
    out.y = mY.sample(s);
    out.z = mZ.sample(s);
    if (mHeading) out.heading = mHeading->sample(s);
    if (mPitch) out.pitch = mPitch->sample(s);
    if (mRoll) out.roll = mRoll->sample(s);
    return out;
  }
  const double legS = mLapS - (mJoinS - mFirstS);
  double t = legT;
  std::size_t piece = 0;
  while (piece + 1 < mLeg.size() && t > mLeg[piece].durationS) t -= mLeg[piece++].durationS;
  out.x = mLeg[piece].axis[0].at(t);
  out.y = mLeg[piece].axis[1].at(t);
  out.z = mLeg[piece].axis[2].at(t);
  const double angleT = std::min(legT, legS);
  if (mLegAngles[0]) out.heading = mLegAngles[0]->at(angleT);
  if (mLegAngles[1]) out.pitch = mLegAngles[1]->at(angleT);
  if (mLegAngles[2]) out.roll = mLegAngles[2]->at(angleT);
  return out;
}

glm::dvec3 ScriptedTrajectory::velocityAtSeconds(double s) const noexcept {
  if (mEnd != FlightEnd::Loop && s > mDurationS) return glm::dvec3(0.0);  // holding still
  const Samples p = samplesAt(s);
  return {p.x.slope, p.y.slope, p.z.slope};
}

Pose ScriptedTrajectory::poseAtSeconds(double s) const noexcept {
  const Samples p = samplesAt(s);
  const SplineSample& x = p.x;
  const SplineSample& y = p.y;
  const SplineSample& z = p.z;
  Pose pose;
  pose.positionM = {x.value, y.value, z.value};
  if (mTerrainHeight) {
    // Lift the eye smoothly (C¹) where the path comes within 2c of the lift floor: height above it
    // d ≥ 2c is kept, below that it becomes c + max(d, 0)² / 4c, never less than c. The lifted
    // climb rate lies between the path's and the floor's.
    const double c = mClearanceM;
    const double d = z.value - liftFloorM(s, mTerrainHeight(x.value, y.value));
    if (c > 0.0 && d < 2.0 * c) {
      const double above = std::max(d, 0.0);
      pose.positionM.z += c + above * above / (4.0 * c) - d;
    } else if (c <= 0.0 && d < 0.0) {
      pose.positionM.z -= d;
    }
  }

  const double groundSpeed2 = x.slope * x.slope + y.slope * y.slope;
  const double groundSpeed = std::sqrt(groundSpeed2);
  // Heading clockwise from north along the ground track; its rate from the turning of the track.
  pose.headingRad = p.heading ? p.heading->value : std::atan2(x.slope, y.slope);
  pose.pitchRad = p.pitch ? p.pitch->value : std::atan2(z.slope, groundSpeed) + mCameraPitchOffsetRad;
  if (p.roll) {
    pose.rollRad = p.roll->value;
  } else if (groundSpeed2 > 1e-6) {
    const double headingRate = (y.slope * x.curvature - x.slope * y.curvature) / groundSpeed2;
    pose.rollRad = std::atan(groundSpeed * headingRate / kGravityMps2);
  }
  return pose;
}

void ScriptedTrajectory::setTerrainFloor(TerrainHeightFn terrainHeight) {
  mTerrainHeight = std::move(terrainHeight);
  mLiftFloorM.clear();
  if (!mTerrainHeight) return;
  // One lap of a loop (the samples wrap round) or the flight to its end (then held)
  const bool loop = mEnd == FlightEnd::Loop;
  const double spanS = loop ? mLapS : mDurationS - mFirstS;
  const int n = std::max(2, static_cast<int>(std::ceil(spanS / kLiftStepS)));
  mLiftStepS = spanS / n;
  const int count = loop ? n : n + 1;
  std::vector<glm::dvec2> track(static_cast<std::size_t>(count));
  std::vector<double> ground(track.size());
  for (int i = 0; i < count; ++i) {
    const Samples p = samplesAt(mFirstS + i * mLiftStepS);
    track[i] = {p.x.value, p.y.value};
    ground[i] = mTerrainHeight(p.x.value, p.y.value);
  }
  // The terrain raised to a cone of the lift gradient round every sample. Ground farther than
  // relief / gradient (straight across, wherever the flight passes it) raises no cone above the
  // lowest ground: only samples within that distance in x and y are compared, found in x order.
  const double relief =
      *std::max_element(ground.begin(), ground.end()) - *std::min_element(ground.begin(), ground.end());
  const double reachM = relief / kMaxLiftGradient;
  std::vector<int> byX(track.size());
  std::iota(byX.begin(), byX.end(), 0);
  std::sort(byX.begin(), byX.end(), [&](int a, int b) { return track[a].x < track[b].x; });
  std::vector<double> coned(ground);
  for (int i = 0; i < count; ++i) {
    auto k = std::partition_point(byX.begin(), byX.end(), [&](int j) { return track[j].x < track[i].x - reachM; });
    for (; k != byX.end() && track[*k].x <= track[i].x + reachM; ++k) {
      if (std::abs(track[*k].y - track[i].y) > reachM) continue;
      coned[i] = std::max(coned[i], ground[*k] - kMaxLiftGradient * glm::distance(track[i], track[*k]));
    }
  }
  // Two passes of a ±0.15 s box make the floor's slope change gradually (between samples it is
  // interpolated linearly). What they take off the cones' tops is put back where it was taken:
  // each sample's loss, widened to the passes' reach and smoothed the same way, is at least the
  // loss there, so the floor still holds the terrain.
  const auto at = [&](int i) {  // a loop's samples wrap round; the ends of a flight are held
    return loop ? ((i % count) + count) % count : std::clamp(i, 0, count - 1);
  };
  constexpr double kSmoothingHalfS = 0.15;
  const int half = std::max(1, static_cast<int>(std::lround(kSmoothingHalfS / mLiftStepS)));
  const auto smoothed = [&](std::vector<double> v) {
    for (int pass = 0; pass < 2; ++pass) {
      const std::vector<double> in = v;
      for (int i = 0; i < count; ++i) {
        double sum = 0.0;
        for (int k = -half; k <= half; ++k) sum += in[at(i + k)];
        v[i] = sum / (2 * half + 1);
      }
    }
    return v;
  };
  std::vector<double> floor = smoothed(coned);
  std::vector<double> taken(track.size());
  for (int i = 0; i < count; ++i) taken[i] = std::max(0.0, coned[i] - floor[i]);
  std::vector<double> loss(track.size(), 0.0);
  for (int i = 0; i < count; ++i) {
    for (int k = -2 * half; k <= 2 * half; ++k) loss[i] = std::max(loss[i], taken[at(i + k)]);
  }
  loss = smoothed(std::move(loss));
  for (int i = 0; i < count; ++i) floor[i] += loss[i];
  mLiftFloorM = std::move(floor);
}

double ScriptedTrajectory::liftFloorM(double seconds, double groundM) const noexcept {
  if (mLiftFloorM.empty() || !std::isfinite(seconds)) return groundM;
  if (seconds < mFirstS) return std::max(groundM, mLiftFloorM.front());  // before the flight: straight on
  const double count = static_cast<double>(mLiftFloorM.size());
  double at = (seconds - mFirstS) / mLiftStepS;
  at = mEnd == FlightEnd::Loop ? std::fmod(at, count) : std::min(at, count - 1.0);
  const auto i = static_cast<std::size_t>(at);
  const std::size_t next =
      mEnd == FlightEnd::Loop ? (i + 1) % mLiftFloorM.size() : std::min(i + 1, mLiftFloorM.size() - 1);
  const double t = at - static_cast<double>(i);
  return std::max(groundM, mLiftFloorM[i] + (mLiftFloorM[next] - mLiftFloorM[i]) * t);
}

Pose ScriptedTrajectory::poseAt(TimePoint t) const noexcept { return poseAtSeconds(toSeconds(t - mStart)); }

ScriptedTrajectory ScriptedTrajectory::load(const std::string& path) { return readFlightFile(path).ownship; }

}  // namespace fieldcast::motion
