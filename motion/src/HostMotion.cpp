// The host-driven motion source: samples placed on the IG clock by the host clock estimate,
// interpolated (cubic Hermite with the host's rates, else linear) and extrapolated at constant
// rates for a bounded time. The predictor is described in HostMotion.h.
#include <motion/HostMotion.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fieldcast::motion {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// `angle` in [−π, π].
double wrapPi(double angle) noexcept { return std::remainder(angle, kTwoPi); }

bool finite(const glm::dvec3& v) noexcept { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool finite(const HostSample& s) noexcept {
  const Pose& p = s.pose;
  if (!std::isfinite(s.hostTimeS) || !finite(p.positionM) || !std::isfinite(p.headingRad) ||
      !std::isfinite(p.pitchRad) || !std::isfinite(p.rollRad)) {
    return false;
  }
  return !s.hasRates || (finite(s.velocityMps) && finite(s.angularRateRadS));
}

/// Heading, pitch, roll as a vector, with heading and roll moved by whole turns to within half a
/// turn of `near` (so differences take the shortest arc).
glm::dvec3 anglesNear(const Pose& p, const glm::dvec3& near) noexcept {
  return {near.x + wrapPi(p.headingRad - near.x), p.pitchRad, near.z + wrapPi(p.rollRad - near.z)};
}
glm::dvec3 angles(const Pose& p) noexcept { return {p.headingRad, p.pitchRad, p.rollRad}; }

Pose makePose(const glm::dvec3& positionM, const glm::dvec3& hpr) noexcept {
  return Pose{positionM, wrapPi(hpr.x), hpr.y, wrapPi(hpr.z)};
}

/// a + w·(b − a), angles by the shortest arc.
Pose mix(const Pose& a, const Pose& b, double w) noexcept {
  const glm::dvec3 from = angles(a);
  return makePose(a.positionM + w * (b.positionM - a.positionM), from + w * (anglesNear(b, from) - from));
}

/// Cubic Hermite between values p0, p1 with slopes m0, m1 (per unit s), at s in [0, 1].
glm::dvec3 hermite(const glm::dvec3& p0, const glm::dvec3& m0, const glm::dvec3& p1, const glm::dvec3& m1,
                   double s) noexcept {
  const double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1;
}

}  // namespace

HostMotion::HostMotion(HostMotionOptions options, Pose initial) noexcept
    : mOptions(options), mInitial(initial), mPublished(Snapshot{}) {}

void HostMotion::addSample(const HostSample& sample) noexcept {
  if (!finite(sample)) {
    mInvalid.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  if (mNewHistory) {
    mNewHistory = false;
    mDraft.count = 0;
    mDraft.blending = false;
  }
  if (mDraft.count > 0) {
    const KeptSample& newest = mDraft.samples[mDraft.count - 1];
    const Nanoseconds clockStep = sample.arrival - mDraft.clock.toLocal(sample.hostTimeS);
    const auto framesBack = static_cast<std::int32_t>(newest.hostFrame - sample.hostFrame);
    if (std::chrono::abs(clockStep) > mOptions.restartStep ||
        framesBack > static_cast<std::int64_t>(mOptions.restartFrames)) {
      // A new host clock (or a new run): nothing before it means anything now.
      mClock.reset();
      mDraft = Snapshot{};
      mRestarts.fetch_add(1, std::memory_order_relaxed);
    } else if (sample.hostTimeS < newest.hostTimeS) {
      mReordered.fetch_add(1, std::memory_order_relaxed);
      return;
    } else if (sample.hostTimeS == newest.hostTimeS) {
      mDuplicates.fetch_add(1, std::memory_order_relaxed);
      return;
    } else if (sample.arrival - mDraft.clock.toLocal(newest.hostTimeS) > mOptions.maxExtrapolation) {
      // The pose was held when this sample arrived: blend from what was shown, and start a new
      // history (a finite difference across the silence would give a wrong velocity).
      mDraft.blendStart = sample.arrival + mOptions.resumeLead;
      mDraft.blendFrom = evaluate(mDraft, mDraft.blendStart);
      mDraft.blending = true;
      mDraft.count = 0;
    }
  }
  if (mDraft.blending && sample.arrival >= mDraft.blendStart + mOptions.resumeBlend) mDraft.blending = false;

  mClock.add(sample.hostTimeS, sample.arrival);
  mDraft.clock = mClock.mapping();
  if (mDraft.count == kKeptSamples) {
    std::copy(mDraft.samples.begin() + 1, mDraft.samples.end(), mDraft.samples.begin());
    --mDraft.count;
  }
  mDraft.samples[mDraft.count++] =
      KeptSample{sample.hostTimeS, sample.pose,    sample.velocityMps, sample.angularRateRadS,
                 sample.hostFrame, sample.arrival, sample.hasRates,    sample.smooth};
  mPublished.store(mDraft);
  mAccepted.fetch_add(1, std::memory_order_relaxed);
}

Pose HostMotion::poseAt(TimePoint t) const noexcept { return evaluate(mPublished.load(), t); }

Pose HostMotion::evaluate(const Snapshot& s, TimePoint t) const noexcept {
  if (s.count == 0) return mInitial;
  const Pose onTrack = track(s, t);
  if (!s.blending || !s.samples[s.count - 1].smooth || t >= s.blendStart + mOptions.resumeBlend) return onTrack;
  const double u = t <= s.blendStart ? 0.0 : toSeconds(t - s.blendStart) / toSeconds(mOptions.resumeBlend);
  return mix(s.blendFrom, onTrack, u * u * (3.0 - 2.0 * u));  // smoothstep: no kink at either end
}

Pose HostMotion::track(const Snapshot& s, TimePoint t) const noexcept {
  if (!s.samples[s.count - 1].smooth) {  // the host asked for its poses as sent
    const KeptSample& asSent = s.samples[sampleIndexAt(s, t)];
    return makePose(asSent.pose.positionM, angles(asSent.pose));
  }
  const KeptSample& oldest = s.samples[0];
  if (t <= s.clock.toLocal(oldest.hostTimeS)) return makePose(oldest.pose.positionM, angles(oldest.pose));

  const KeptSample& newest = s.samples[s.count - 1];
  const TimePoint newestLocal = s.clock.toLocal(newest.hostTimeS);
  if (t >= newestLocal) {
    // Constant velocity and angle rates from the newest sample, for at most maxExtrapolation.
    const double dtS = toSeconds(std::min(t - newestLocal, mOptions.maxExtrapolation));
    glm::dvec3 velocity{0.0}, angleRate{0.0};
    if (newest.hasRates) {
      velocity = newest.velocityMps;
      angleRate = newest.angularRateRadS;
    } else if (s.count >= 2) {
      const KeptSample& before = s.samples[s.count - 2];
      const double spanS = toSeconds(newestLocal - s.clock.toLocal(before.hostTimeS));
      if (spanS > 0.0) {
        const glm::dvec3 newestAngles = angles(newest.pose);
        velocity = (newest.pose.positionM - before.pose.positionM) / spanS;
        angleRate = (newestAngles - anglesNear(before.pose, newestAngles)) / spanS;
      }
    }
    return makePose(newest.pose.positionM + dtS * velocity, angles(newest.pose) + dtS * angleRate);
  }

  // Between samples i and i + 1.
  std::uint32_t i = s.count - 2;
  while (i > 0 && s.clock.toLocal(s.samples[i].hostTimeS) > t) --i;
  const KeptSample& a = s.samples[i];
  const KeptSample& b = s.samples[i + 1];
  const TimePoint aLocal = s.clock.toLocal(a.hostTimeS);
  const double spanS = toSeconds(s.clock.toLocal(b.hostTimeS) - aLocal);
  if (!(spanS > 0.0)) return makePose(b.pose.positionM, angles(b.pose));
  const double u = toSeconds(t - aLocal) / spanS;
  const glm::dvec3 aAngles = angles(a.pose);
  const glm::dvec3 bAngles = anglesNear(b.pose, aAngles);
  if (a.hasRates && b.hasRates) {
    return makePose(hermite(a.pose.positionM, spanS * a.velocityMps, b.pose.positionM, spanS * b.velocityMps, u),
                    hermite(aAngles, spanS * a.angularRateRadS, bAngles, spanS * b.angularRateRadS, u));
  }
  return makePose(a.pose.positionM + u * (b.pose.positionM - a.pose.positionM), aAngles + u * (bAngles - aAngles));
}

HostSampleUsed HostMotion::sampleUsedAt(TimePoint t) const noexcept {
  const Snapshot s = mPublished.load();
  if (s.count == 0) return HostSampleUsed{};
  const KeptSample& used = s.samples[sampleIndexAt(s, t)];
  return HostSampleUsed{true, used.hostFrame, used.arrival, used.hostTimeS};
}

std::uint32_t HostMotion::sampleIndexAt(const Snapshot& s, TimePoint t) noexcept {
  std::uint32_t k = 0;
  if (!s.samples[s.count - 1].smooth) {
    k = s.count - 1;
    while (k > 0 && s.clock.toLocal(s.samples[k].hostTimeS) > t) --k;
    return k;
  }
  while (k + 1 < s.count && s.clock.toLocal(s.samples[k].hostTimeS) < t) ++k;
  return k;
}

HostPoseState HostMotion::state(TimePoint now) const noexcept {
  const Snapshot s = mPublished.load();
  if (s.count == 0) return HostPoseState::NoSamples;
  const Nanoseconds age = now - s.clock.toLocal(s.samples[s.count - 1].hostTimeS);
  if (age <= mOptions.trackingGap) return HostPoseState::Tracking;
  if (age <= mOptions.maxExtrapolation) return HostPoseState::Extrapolating;
  return HostPoseState::Holding;
}

HostMotion::Counters HostMotion::counters() const noexcept {
  return Counters{mAccepted.load(std::memory_order_relaxed), mReordered.load(std::memory_order_relaxed),
                  mDuplicates.load(std::memory_order_relaxed), mRestarts.load(std::memory_order_relaxed),
                  mInvalid.load(std::memory_order_relaxed)};
}

TimePoint HostMotion::toLocal(double hostTimeS) const noexcept { return mPublished.load().clock.toLocal(hostTimeS); }

HostClockMapping HostMotion::clockMapping() const noexcept { return mPublished.load().clock; }

}  // namespace fieldcast::motion
