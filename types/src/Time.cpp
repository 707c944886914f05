#include <fieldcast/Time.h>

#include <cerrno>
#include <cmath>

namespace fieldcast {

MonotonicClock::time_point MonotonicClock::now() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return fromTimespec(ts);
}

Nanoseconds fromSeconds(double seconds) noexcept {
  return Nanoseconds{static_cast<std::int64_t>(std::llround(seconds * 1e9))};
}

TimePoint SystemClock::now() const noexcept { return MonotonicClock::now(); }

void SystemClock::sleepUntil(TimePoint deadline) noexcept {
  const timespec ts = toTimespec(deadline);
  // Restart after a signal: the deadline is absolute, so no time is lost by retrying.
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

TimePoint VirtualClock::now() const noexcept { return TimePoint{Nanoseconds{mNowNs.load(std::memory_order_acquire)}}; }

void VirtualClock::sleepUntil(TimePoint deadline) noexcept { advanceTo(deadline); }

void VirtualClock::advance(Nanoseconds d) noexcept {
  if (d.count() > 0) mNowNs.fetch_add(d.count(), std::memory_order_acq_rel);
}

void VirtualClock::advanceTo(TimePoint t) noexcept {
  const std::int64_t target = t.time_since_epoch().count();
  std::int64_t current = mNowNs.load(std::memory_order_acquire);
  while (current < target && !mNowNs.compare_exchange_weak(current, target, std::memory_order_acq_rel)) {
  }
}

}  // namespace fieldcast
