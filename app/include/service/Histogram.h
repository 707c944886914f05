#pragma once
// A wait-free histogram of durations with logarithmic bins (2% wide, 1 µs … 100 s): any thread
// records with one atomic increment and no allocation, so the field thread can record its warp
// time; the metrics thread reads percentiles. Percentiles are exact to within one bin (±1%).

#include <fieldcast/Time.h>

#include <array>
#include <atomic>
#include <cstdint>

namespace fieldcast::app {

/// Percentile summary of a histogram, in seconds.
struct DurationSummary {
  std::uint64_t count = 0;
  double p50S = 0.0;
  double p99S = 0.0;
  double maxS = 0.0;
  double meanS = 0.0;
};

/// Log-binned histogram of non-negative durations.
class DurationHistogram {
 public:
  static constexpr double kMinS = 1e-6;       ///< durations below go in the first bin
  static constexpr double kBinRatio = 1.02;   ///< each bin 2% wider than the one before
  static constexpr std::size_t kBins = 1048;  ///< up to 1e-6 · 1.02^1047 ≈ 1e3 s

  /// Records one duration. Any thread; wait-free, RT-safe.
  void record(Nanoseconds d) noexcept;
  /// Adds every count of `other` (a snapshot) into this histogram. Not RT-safe (1 KB of loads).
  void merge(const DurationHistogram& other) noexcept;
  /// Copies the counts into `out` and zeroes this histogram (counts recorded meanwhile land in
  /// one or the other, never lost).
  void drainInto(DurationHistogram& out) noexcept;
  /// Count, p50, p99, max and mean. Any thread.
  DurationSummary summary() const noexcept;
  /// Value (seconds) at quantile q ∈ [0, 1]: the upper edge of the bin holding it, clamped to max.
  double quantileS(double q) const noexcept;
  std::uint64_t count() const noexcept { return mCount.load(std::memory_order_relaxed); }

  /// Bin of a duration, and the upper edge of a bin, in seconds.
  static std::size_t binOf(double seconds) noexcept;
  static double binUpperS(std::size_t bin) noexcept;

 private:
  std::array<std::atomic<std::uint64_t>, kBins> mBins{};
  std::atomic<std::uint64_t> mCount{0};
  std::atomic<std::int64_t> mSumNs{0};
  std::atomic<std::int64_t> mMaxNs{0};
};

}  // namespace fieldcast::app
