#pragma once
// When a device the latency bench plays (a stick, a host) first sent its newest value: the caller
// changes the value and waits; the device's sending thread notes each send. The instant, on
// CLOCK_MONOTONIC, is the one an end-to-end latency is measured from.

#include <time.h>

#include <chrono>
#include <cstdint>
#include <mutex>
#include <thread>

namespace fieldcast::tools {

class FirstSend {
 public:
  static std::int64_t monotonicNs() noexcept {
    timespec ts{};
    ::clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
  }

  /// Runs `change` (the new value) under the lock and returns its generation.
  template <typename Change>
  std::uint64_t change(Change&& apply) {
    const std::lock_guard lock(mMutex);
    apply();
    return ++mGeneration;
  }
  /// Reads the current value under the lock: `read()`; returns its generation.
  template <typename Read>
  std::uint64_t current(Read&& read) {
    const std::lock_guard lock(mMutex);
    read();
    return mGeneration;
  }
  /// The sending thread sent generation `generation` at `ns`.
  void sent(std::uint64_t generation, std::int64_t ns) {
    const std::lock_guard lock(mMutex);
    if (mSentGeneration != generation) {  // the first send of this value
      mSentGeneration = generation;
      mSentNs = ns;
    }
  }
  /// The instant generation `generation` was first sent, or 0 when it was not within a second.
  std::int64_t waitFor(std::uint64_t generation) {
    for (int i = 0; i < 1000; ++i) {
      {
        const std::lock_guard lock(mMutex);
        if (mSentGeneration == generation) return mSentNs;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return 0;
  }

 private:
  std::mutex mMutex;
  std::uint64_t mGeneration = 0;      // values set so far
  std::uint64_t mSentGeneration = 0;  // the newest value sent ...
  std::int64_t mSentNs = 0;           // ... first sent at this instant
};

}  // namespace fieldcast::tools
