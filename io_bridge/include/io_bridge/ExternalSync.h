#pragma once
// Estimates the period and phase of an external sync (a pulse per video field from a house
// reference or another IG) from its edge timestamps, so the field clock can discipline t_0 and T
// (DESIGN.md §4). Each edge gets a pulse index by rounding its gap to the current period (a
// missing pulse advances the index by two; a glitch shorter than half a period is rejected), then
// t = t_0 + k·T is fitted by least squares over the last edges.

#include <fieldcast/Time.h>

#include <array>
#include <cstdint>

namespace fieldcast::io {

/// What the sync input says. Trivially copyable (published through a SeqLock).
struct SyncEstimate {
  TimePoint lastPulse{};       ///< fitted time of the newest pulse (a phase reference)
  double periodNs = 0.0;       ///< fitted period
  double jitterRmsNs = 0.0;    ///< RMS residual of the fit
  std::uint64_t pulses = 0;    ///< pulses accepted
  std::uint64_t glitches = 0;  ///< edges rejected as too close to the previous pulse
  std::uint64_t missed = 0;    ///< pulses inferred missing from gaps
  bool locked = false;         ///< enough pulses, small residual: safe to discipline the clock

  /// Predicted time of the pulse `n` periods after lastPulse. RT-safe.
  TimePoint predict(std::int64_t n) const noexcept {
    return lastPulse + Nanoseconds{static_cast<std::int64_t>(static_cast<double>(n) * periodNs)};
  }
};

/// Least-squares sync estimator over a sliding window. One thread feeds it. RT-safe (no allocation).
class ExternalSyncEstimator {
 public:
  static constexpr std::size_t kWindow = 64;

  /// `nominal`: the expected pulse rate (e.g. 60000/1001); pulses within ±`tolerance` of a whole
  /// number of periods are accepted.
  explicit ExternalSyncEstimator(RationalRate nominal, double tolerance = 0.25) noexcept;

  /// Feeds one pulse (rising edge). RT-safe.
  void onPulse(TimePoint t) noexcept;
  /// The current estimate. RT-safe.
  SyncEstimate estimate() const noexcept { return mEstimate; }

 private:
  void fit() noexcept;

  double mNominalNs;
  double mTolerance;
  std::array<std::int64_t, kWindow> mIndex{};  // pulse index k
  std::array<std::int64_t, kWindow> mTimeNs{};
  std::size_t mCount = 0;  // valid entries (≤ kWindow)
  std::size_t mHead = 0;   // next slot
  std::int64_t mLastIndex = 0;
  std::int64_t mLastTimeNs = 0;
  SyncEstimate mEstimate;
};

}  // namespace fieldcast::io
