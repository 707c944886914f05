#pragma once
// A single-writer, many-reader "latest value" cell: the writer never waits, readers never block
// the writer and retry only while a write is in progress. Used to publish the newest control
// state, flight state and figures between threads without locks.
//
// The value is copied word by word through relaxed atomics, so the (intended) race between a
// reader and the writer is well-defined C++ and ThreadSanitizer-clean.

#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace fieldcast {

/// Latest-value cell for a trivially copyable T. One writer thread; any number of readers.
template <typename T>
class SeqLock {
  static_assert(std::is_trivially_copyable_v<T>, "SeqLock holds trivially copyable values only");
  static constexpr std::size_t kWords = (sizeof(T) + sizeof(std::uint64_t) - 1) / sizeof(std::uint64_t);

 public:
  explicit SeqLock(const T& initial = T{}) noexcept { store(initial); }

  /// Publishes `value`. Writer thread only. Wait-free, RT-safe.
  void store(const T& value) noexcept {
    std::array<std::uint64_t, kWords> words{};
    // The value's bytes as they are: an empty std::optional's payload or padding may be
    // indeterminate, and GCC warns that they are copied; load() copies them back unread.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
    std::memcpy(words.data(), &value, sizeof(T));
    const std::uint64_t seq = mSequence.load(std::memory_order_relaxed);
    mSequence.store(seq + 1, std::memory_order_relaxed);  // odd: a write is in progress
    std::atomic_thread_fence(std::memory_order_release);
    for (std::size_t i = 0; i < kWords; ++i) mWords[i].store(words[i], std::memory_order_relaxed);
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
    mSequence.store(seq + 2, std::memory_order_release);
  }

  /// The latest complete value. Any thread. Lock-free, RT-safe (retries only across a write).
  T load() const noexcept {
    std::array<std::uint64_t, kWords> words{};
    for (;;) {
      const std::uint64_t before = mSequence.load(std::memory_order_acquire);
      if (before & 1u) continue;
      for (std::size_t i = 0; i < kWords; ++i) words[i] = mWords[i].load(std::memory_order_relaxed);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (mSequence.load(std::memory_order_relaxed) == before) break;
    }
    T value;
    std::memcpy(static_cast<void*>(&value), words.data(), sizeof(T));  // T is trivially copyable
    return value;
  }

  /// Number of stores so far (the sequence advances by 2 per store).
  std::uint64_t version() const noexcept { return mSequence.load(std::memory_order_acquire) / 2; }

 private:
  std::atomic<std::uint64_t> mSequence{0};
  std::array<std::atomic<std::uint64_t>, kWords> mWords{};
};

}  // namespace fieldcast
