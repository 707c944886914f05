#pragma once
// The ownship's pose from a simulator host (issue 19, DESIGN.md §4): the CIGI receiver hands over
// each Entity Control pose (with Rate Control's rates when the host sends them) stamped with the
// host's timestamp; the renderer and the field loop ask for the pose at any IG instant.
//
// Timing model. Each sample is placed on the IG clock at toLocal(hostTime) — when the host says
// the pose was true, not when the datagram arrived — through HostClockEstimator (offset and drift
// from the lower envelope of arrival − hostTime, so network jitter does not move the poses).
//
// Predictor. Between two kept samples: cubic Hermite in position and angles when both carry rates,
// else linear; heading and roll take the shortest arc (they wrap at ±π). After the newest sample:
// constant velocity and constant angle rates from the newest sample — the host's rates when it sent
// them, else the finite difference of the newest two samples — for at most maxExtrapolation, then
// the pose reached there is held. Before the oldest kept sample: the oldest.
//
// Faults. A sample older than the newest (by host time) is dropped as reordered, one at the same
// host time as a duplicate. A restart — the sample's arrival more than restartStep away from where
// the clock estimate puts its host time (the host clock jumped back or forward), or the host frame
// number falling back by more than restartFrames — forgets the clock estimate and the history and
// follows the new track at once. When samples return after the pose was held, the pose blends from
// the held pose to the new track over resumeBlend (smoothstep), starting resumeLead after the
// arrival: instants up to that far ahead may already have been shown held, and keep that pose.

#include <motion/HostClockEstimator.h>
#include <motion/MotionSource.h>

#include <fieldcast/Pose.h>
#include <fieldcast/SeqLock.h>
#include <fieldcast/Time.h>

#include <glm/vec3.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>

namespace fieldcast::motion {

/// One pose report from the host (CIGI Entity Control, with Rate Control when present).
struct HostSample {
  double hostTimeS = 0.0;           ///< host timestamp, seconds (unwrapped by the receiver)
  TimePoint arrival{};              ///< IG clock when the datagram arrived
  Pose pose;                        ///< world pose (database-local metres, radians)
  bool hasRates = false;            ///< Rate Control gave rates for this entity
  glm::dvec3 velocityMps{0.0};      ///< world-frame linear velocity, m/s (when hasRates)
  glm::dvec3 angularRateRadS{0.0};  ///< d/dt of (heading, pitch, roll), rad/s (when hasRates)
  std::uint32_t hostFrame = 0;      ///< host frame number
  /// IG Control's extrapolation/interpolation enable. Off, the pose at any instant is the newest
  /// sample at or before it, as received: no interpolation, no extrapolation, no resume blend.
  bool smooth = true;
};

/// Tuning of HostMotion.
struct HostMotionOptions {
  Nanoseconds maxExtrapolation = std::chrono::milliseconds{250};  ///< beyond the newest sample, then hold
  Nanoseconds resumeBlend = std::chrono::milliseconds{200};       ///< held pose → new track after a silence
  Nanoseconds resumeLead = std::chrono::milliseconds{40};         ///< furthest ahead of now a client asks (fields)
  Nanoseconds trackingGap = std::chrono::milliseconds{50};        ///< newest sample older than this: Extrapolating
  Nanoseconds restartStep = std::chrono::seconds{1};              ///< host clock step that means a restart
  std::uint32_t restartFrames = 60;                               ///< host frame number falling back by more: restart
};

/// What the pose at an instant is made of.
enum class HostPoseState : std::uint8_t {
  NoSamples,      ///< nothing received yet: the initial pose
  Tracking,       ///< the newest sample is younger than trackingGap
  Extrapolating,  ///< the host is late or silent, within maxExtrapolation
  Holding,        ///< silent for longer: the pose reached at maxExtrapolation is held
};

/// Which host sample a pose was made from (for the per-field record and arrival → field latency).
struct HostSampleUsed {
  bool valid = false;           ///< false before the first sample (the initial pose)
  std::uint32_t hostFrame = 0;  ///< the sample's host frame number
  TimePoint arrival{};          ///< IG clock when its datagram arrived
  double hostTimeS = 0.0;       ///< its host timestamp, seconds

  friend bool operator==(const HostSampleUsed&, const HostSampleUsed&) = default;
};

/// The host-driven motion source. addSample from one thread (the receiver); poseAt, state,
/// toLocal and counters from any thread, lock-free (a SeqLock of a small snapshot).
class HostMotion final : public MotionSource {
 public:
  static constexpr std::size_t kKeptSamples = 8;  ///< history for poseAt (133 ms at 60 Hz)

  /// What happened to the samples so far.
  struct Counters {
    std::uint64_t accepted = 0;
    std::uint64_t reordered = 0;   ///< older than the newest by host time: dropped
    std::uint64_t duplicates = 0;  ///< same host time as the newest: dropped
    std::uint64_t restarts = 0;    ///< host clock or frame number jumped: history reset
    std::uint64_t invalid = 0;     ///< non-finite time, pose or rates: dropped
  };

  /// `initial` is the pose until the first sample arrives.
  explicit HostMotion(HostMotionOptions options = {}, Pose initial = {}) noexcept;

  /// Takes one sample. One thread only (the receiver). O(HostClockEstimator::kWindow), RT-safe.
  void addSample(const HostSample& sample) noexcept;
  /// The next sample starts a new history (the receiver's thread): a database switch moved the
  /// world the poses are in, so no pose is interpolated across it. The clock estimate stays.
  void startNewHistory() noexcept { mNewHistory = true; }
  /// The pose at IG instant `t` (world metres, radians; heading and roll in [−π, π]).
  /// Any thread, lock-free, RT-safe.
  Pose poseAt(TimePoint t) const noexcept override;
  /// The newest sample the pose at IG instant `t` depends on: the newest kept sample when `t` is
  /// at or after it (extrapolation), the later of the two samples `t` lies between
  /// (interpolation), the oldest when `t` precedes it. Any thread, lock-free, RT-safe.
  HostSampleUsed sampleUsedAt(TimePoint t) const noexcept;
  /// The link's state seen at IG instant `now`. Any thread, RT-safe.
  HostPoseState state(TimePoint now) const noexcept;
  /// Sample counts. Any thread, RT-safe.
  Counters counters() const noexcept;
  /// The IG instant of host time `hostTimeS` by the current clock estimate (the epoch before the
  /// first sample). Any thread, RT-safe.
  TimePoint toLocal(double hostTimeS) const noexcept;
  /// The current clock estimate. Any thread, RT-safe.
  HostClockMapping clockMapping() const noexcept;

 private:
  struct KeptSample {
    double hostTimeS;
    Pose pose;
    glm::dvec3 velocityMps;
    glm::dvec3 angularRateRadS;
    std::uint32_t hostFrame;
    TimePoint arrival;
    bool hasRates;
    bool smooth;
  };
  /// Everything poseAt needs, published whole.
  struct Snapshot {
    HostClockMapping clock;
    std::array<KeptSample, kKeptSamples> samples;  // oldest first
    std::uint32_t count;
    bool blending;  // resuming after a hold
    TimePoint blendStart;
    Pose blendFrom;
  };

  Pose evaluate(const Snapshot& s, TimePoint t) const noexcept;
  Pose track(const Snapshot& s, TimePoint t) const noexcept;
  /// The kept sample the pose at `t` is made from: the newest at or before t for a host that
  /// turned smoothing off, the first at or after t otherwise (the later of an interpolated pair).
  static std::uint32_t sampleIndexAt(const Snapshot& s, TimePoint t) noexcept;

  HostMotionOptions mOptions;
  Pose mInitial;
  HostClockEstimator mClock;  // writer only
  bool mNewHistory = false;   // writer only: startNewHistory() was called
  Snapshot mDraft{};          // writer only: the next snapshot
  SeqLock<Snapshot> mPublished;
  std::atomic<std::uint64_t> mAccepted{0}, mReordered{0}, mDuplicates{0}, mRestarts{0}, mInvalid{0};
};

}  // namespace fieldcast::motion
