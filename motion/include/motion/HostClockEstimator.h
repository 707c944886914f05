#pragma once
// The host's clock seen from the IG's (DESIGN.md §4): a simulator host stamps each message with
// its own clock; the IG needs those instants on its monotonic clock. Only one-way traffic is
// available, so the estimate is "host time → the IG instant the datagram would have arrived with
// the smallest network delay seen": the minimum one-way delay itself cannot be observed and stays
// inside the mapping (on 127.0.0.1 or a LAN it is tens of microseconds).

#include <fieldcast/Time.h>

#include <array>
#include <cstddef>

namespace fieldcast::motion {

/// An affine map from host seconds to IG instants: local = localRef + (h − hostRef)·(1 + drift)
/// + offset. Trivially copyable (it is published through a SeqLock). Precise to well under a
/// microsecond for days after hostRef.
struct HostClockMapping {
  double hostRefS = 0.0;    ///< host time of the first sample since the last reset, seconds
  TimePoint localRef{};     ///< IG arrival of that sample
  double offsetS = 0.0;     ///< minimum-delay line at hostRefS: local − localRef − (h − hostRefS), seconds
  double driftRatio = 0.0;  ///< IG seconds per host second − 1 (a host 100 ppm fast gives ≈ −1e-4)
  bool valid = false;       ///< false until the first sample

  /// The IG instant of host time `hostTimeS`; the epoch when not valid. RT-safe.
  TimePoint toLocal(double hostTimeS) const noexcept;
  /// How fast the host clock runs against the IG clock, parts per million (positive: host fast).
  double hostDriftPpm() const noexcept { return (1.0 / (1.0 + driftRatio) - 1.0) * 1e6; }
};

/// Offset and drift of a host clock from (host timestamp, IG arrival) pairs, robust to network
/// jitter: the points y = arrival − hostTime of a sliding window (the lowest of each kBucketS of
/// host time, which keeps every point the estimate can rest on) lie above the minimum-delay line,
/// so the estimate is the line under all of them that lies closest to them on average — the lower
/// convex hull's edge spanning the window's mean host time (the linear-programming skew estimator
/// of Moon, Skelly & Towsley, "Estimation and removal of clock skew from network delay
/// measurements", INFOCOM 1999). A slope from a short window is worse than none (8 ms of jitter
/// over 1 s is ±500 ppm), so until the window spans kMinDriftSpanS the drift stays at its last
/// estimate (0 at start) and the offset is the lowest point: the first samples already give an
/// offset good to their smallest delay, off by at most drift × 4 s meanwhile (0.4 ms at 100 ppm).
/// Drift is clamped to ±kMaxDriftRatio.
/// Fixed capacity, never allocates; not thread-safe (one writer; publish mapping() by copy).
class HostClockEstimator {
 public:
  static constexpr double kBucketS = 0.1;         ///< the window keeps the lowest point of each bucket of host time
  static constexpr std::size_t kWindow = 512;     ///< buckets at most ...
  static constexpr double kWindowSpanS = 30.0;    ///< ... over at most this much host time
  static constexpr double kMinDriftSpanS = 4.0;   ///< window span before the drift is fitted
  static constexpr double kMaxDriftRatio = 1e-3;  ///< ±1000 ppm: any real oscillator is inside

  /// Adds one (host time, arrival) pair; host times must increase (the caller drops the others).
  /// O(kWindow). RT-safe.
  void add(double hostTimeS, TimePoint arrival) noexcept;
  /// Forgets every sample (host restart). RT-safe.
  void reset() noexcept;
  /// The current estimate. RT-safe.
  const HostClockMapping& mapping() const noexcept { return mMapping; }
  /// Points (bucket minima) in the window.
  std::size_t size() const noexcept { return mSize; }

 private:
  struct Point {
    double xS;  ///< host time − hostRefS
    double yS;  ///< (arrival − localRef) − xS
  };
  const Point& point(std::size_t i) const noexcept { return mPoints[(mFirst + i) % kWindow]; }
  void fit() noexcept;

  std::array<Point, kWindow> mPoints{};
  std::array<std::size_t, kWindow> mHull{};  // indices (0 = oldest) of the lower hull's vertices
  std::size_t mFirst = 0;
  std::size_t mSize = 0;
  HostClockMapping mMapping;
};

}  // namespace fieldcast::motion
