#pragma once
// Time in Fieldcast: one monotonic clock (CLOCK_MONOTONIC), every instant in nanoseconds
// (DESIGN.md §4). The clock is an interface so timing logic runs in virtual time in tests.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <ctime>

namespace fieldcast {

/// Duration in nanoseconds.
using Nanoseconds = std::chrono::nanoseconds;

/// std::chrono clock over CLOCK_MONOTONIC: the one time base of every timestamp in Fieldcast,
/// including kernel evdev/gpio event times (which the kernel stamps on the same clock).
struct MonotonicClock {
  using duration = Nanoseconds;
  using rep = duration::rep;
  using period = duration::period;
  using time_point = std::chrono::time_point<MonotonicClock, duration>;
  static constexpr bool is_steady = true;  // NOLINT(readability-identifier-naming): std::chrono requires this name
  /// Reads CLOCK_MONOTONIC. RT-safe.
  static time_point now() noexcept;
};
static_assert(MonotonicClock::is_steady);

/// An instant on CLOCK_MONOTONIC, nanosecond resolution.
using TimePoint = MonotonicClock::time_point;

/// Converts a kernel timespec on CLOCK_MONOTONIC to a TimePoint. RT-safe.
constexpr TimePoint fromTimespec(const timespec& ts) noexcept {
  return TimePoint{Nanoseconds{std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec}};
}
/// Converts a TimePoint to a timespec (for clock_nanosleep). RT-safe.
constexpr timespec toTimespec(TimePoint t) noexcept {
  const std::int64_t ns = t.time_since_epoch().count();
  std::int64_t sec = ns / 1'000'000'000;
  std::int64_t rem = ns % 1'000'000'000;
  if (rem < 0) {  // keep tv_nsec in [0, 1e9) for instants before the epoch
    rem += 1'000'000'000;
    sec -= 1;
  }
  return timespec{static_cast<time_t>(sec), static_cast<long>(rem)};
}
/// Seconds as a double, for figures and physics; never for scheduling.
constexpr double toSeconds(Nanoseconds d) noexcept { return static_cast<double>(d.count()) * 1e-9; }
/// Nanoseconds nearest to a duration given in seconds.
Nanoseconds fromSeconds(double seconds) noexcept;

/// An exact rational rate in Hz, such as 60000/1001 for 59.94 fields per second. Periods are
/// never rounded once and accumulated: the k-th tick is computed from k, so there is no drift.
struct RationalRate {
  std::int64_t numerator = 60000;   ///< ticks per `denominator` seconds
  std::int64_t denominator = 1001;  ///< seconds

  /// Rate in Hz as a double, for display.
  constexpr double hz() const noexcept { return static_cast<double>(numerator) / static_cast<double>(denominator); }
  /// Offset of tick k ≥ 0 from tick 0, rounded to the nearest nanosecond. k is split into whole
  /// cycles of `numerator` ticks (exactly `denominator` seconds each) and a remainder, so nothing
  /// overflows for centuries of fields. RT-safe.
  constexpr Nanoseconds tickOffset(std::int64_t k) const noexcept {
    const std::int64_t cycles = k / numerator;
    const std::int64_t rest = k % numerator;
    const std::int64_t cycleNs = denominator * 1'000'000'000;
    return Nanoseconds{cycles * cycleNs + (rest * cycleNs + numerator / 2) / numerator};
  }
  /// One period, rounded to the nearest nanosecond (for display and tolerances only).
  constexpr Nanoseconds period() const noexcept { return tickOffset(1); }
};

/// The source of time for anything that schedules: the system's monotonic clock in the service,
/// a virtual clock in tests.
class Clock {
 public:
  virtual ~Clock() = default;
  /// The current instant. RT-safe.
  virtual TimePoint now() const noexcept = 0;
  /// Blocks until `deadline` (absolute, never relative). Returns at once if it has passed. RT-safe.
  virtual void sleepUntil(TimePoint deadline) noexcept = 0;
};

/// CLOCK_MONOTONIC with clock_nanosleep(TIMER_ABSTIME): sleeping to an absolute deadline means a
/// late wake-up never shifts the following deadlines.
class SystemClock final : public Clock {
 public:
  TimePoint now() const noexcept override;
  void sleepUntil(TimePoint deadline) noexcept override;
};

/// A clock that moves only when told to: sleepUntil() jumps straight to the deadline, advance()
/// adds time. Thread-safe; time never goes backwards.
class VirtualClock final : public Clock {
 public:
  explicit VirtualClock(TimePoint start = TimePoint{}) noexcept : mNowNs(start.time_since_epoch().count()) {}
  TimePoint now() const noexcept override;
  void sleepUntil(TimePoint deadline) noexcept override;
  /// Moves time forward by `d` (negative durations are ignored).
  void advance(Nanoseconds d) noexcept;
  /// Sets the time, if `t` is later than now.
  void advanceTo(TimePoint t) noexcept;

 private:
  std::atomic<std::int64_t> mNowNs;
};

}  // namespace fieldcast
