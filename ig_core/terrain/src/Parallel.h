#pragma once
// A plain fork-join loop for offline jobs (database builds, imports): chunks of an index range are
// handed out dynamically to threads that live for the duration of the call. Not for the frame path.

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace fieldcast::core::detail {

/// Threads to use: `requested` if positive, else every core.
inline int resolveThreads(int requested) noexcept {
  if (requested > 0) return requested;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

/// Calls fn(begin, end) over [0, count) in chunks of `grain`, on `threads` threads (0: all cores).
/// The first exception thrown by any chunk is rethrown after every thread has stopped.
template <typename Fn>
void parallelFor(std::size_t count, int threads, std::size_t grain, Fn&& fn) {
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t chunks = (count + grain - 1) / grain;
  const auto workers = static_cast<std::size_t>(std::min<std::size_t>(resolveThreads(threads), chunks));
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex errorMutex;
  const auto work = [&] {
    for (;;) {
      const std::size_t chunk = next.fetch_add(1);
      if (chunk >= chunks) return;
      try {
        fn(chunk * grain, std::min(count, (chunk + 1) * grain));
      } catch (...) {
        const std::lock_guard lock(errorMutex);
        if (!error) error = std::current_exception();
        next.store(chunks);  // stop handing out work
      }
    }
  };
  if (workers <= 1) {
    work();
  } else {
    std::vector<std::jthread> pool;
    pool.reserve(workers - 1);
    for (std::size_t t = 1; t < workers; ++t) pool.emplace_back(work);
    work();
  }  // jthreads join here
  if (error) std::rethrow_exception(error);
}

}  // namespace fieldcast::core::detail
