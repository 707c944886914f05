// Pose predictors: polynomial extrapolation in time of the newest timed poses.
#include <motion/PosePredictor.h>

#include <cmath>
#include <numbers>

namespace fieldcast::motion {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// `angle` moved by whole turns to within half a turn of `reference`.
double unwrapNear(double angle, double reference) noexcept {
  return reference + std::remainder(angle - reference, kTwoPi);
}

/// The poses of the newest `n` samples with heading and roll unwrapped onto the newest one's
/// branch, and their times in seconds relative to the newest.
template <std::size_t N>
void gather(const PoseHistory& h, std::array<Pose, N>& poses, std::array<double, N>& timesS) noexcept {
  const PoseHistory::Sample& newest = h.fromNewest(0);
  for (std::size_t i = 0; i < N; ++i) {
    const PoseHistory::Sample& s = h.fromNewest(i);
    poses[i] = s.pose;
    poses[i].headingRad = unwrapNear(s.pose.headingRad, newest.pose.headingRad);
    poses[i].rollRad = unwrapNear(s.pose.rollRad, newest.pose.rollRad);
    timesS[i] = toSeconds(s.t - newest.t);
  }
}

/// Σ w_i · pose_i over every component (the weights of a polynomial through the samples).
template <std::size_t N>
Pose combine(const std::array<Pose, N>& poses, const std::array<double, N>& w) noexcept {
  Pose out{};
  out.positionM = {0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < N; ++i) {
    out.positionM += w[i] * poses[i].positionM;
    out.headingRad += w[i] * poses[i].headingRad;
    out.pitchRad += w[i] * poses[i].pitchRad;
    out.rollRad += w[i] * poses[i].rollRad;
  }
  return out;
}

Pose linearThroughNewestTwo(const PoseHistory& h, TimePoint t) noexcept {
  std::array<Pose, 2> poses;
  std::array<double, 2> ts{};
  gather(h, poses, ts);
  const double x = toSeconds(t - h.fromNewest(0).t);
  const double span = ts[0] - ts[1];  // > 0: push() keeps times increasing
  // Lagrange weights of the line through (ts[0], p0) and (ts[1], p1).
  const std::array<double, 2> w{(x - ts[1]) / span, (ts[0] - x) / span};
  return combine(poses, w);
}

}  // namespace

void PoseHistory::push(TimePoint t, const Pose& pose) noexcept {
  if (mSize > 0 && !(t > mSamples[mHead].t)) {
    mSamples[mHead] = {t, pose};  // same or earlier instant: the newer report wins
    return;
  }
  mHead = (mHead + 1) % kCapacity;
  mSamples[mHead] = {t, pose};
  if (mSize < kCapacity) ++mSize;
}

Pose ConstantVelocityPredictor::poseAt(TimePoint t) const noexcept {
  if (mHistory.size() == 0) return Pose{};
  if (mHistory.size() == 1) return mHistory.fromNewest(0).pose;
  return linearThroughNewestTwo(mHistory, t);
}

Pose ConstantAccelerationPredictor::poseAt(TimePoint t) const noexcept {
  if (mHistory.size() == 0) return Pose{};
  if (mHistory.size() == 1) return mHistory.fromNewest(0).pose;
  if (mHistory.size() == 2) return linearThroughNewestTwo(mHistory, t);
  std::array<Pose, 3> poses;
  std::array<double, 3> ts{};
  gather(mHistory, poses, ts);
  const double x = toSeconds(t - mHistory.fromNewest(0).t);
  // Lagrange basis of the parabola through the three sample times.
  std::array<double, 3> w{};
  for (std::size_t i = 0; i < 3; ++i) {
    double num = 1.0, den = 1.0;
    for (std::size_t j = 0; j < 3; ++j) {
      if (j == i) continue;
      num *= x - ts[j];
      den *= ts[i] - ts[j];
    }
    w[i] = num / den;
  }
  return combine(poses, w);
}

}  // namespace fieldcast::motion
