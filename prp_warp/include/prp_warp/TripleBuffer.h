#pragma once
// The renderer → PRP hand-over (DESIGN.md §5): a lock-free triple buffer. The producer always has
// a slot to fill and never waits; the consumer takes the newest complete value without waiting;
// values the consumer never took are simply overwritten (newest complete frame wins).
//
// Three slots rotate between the roles "back" (producer's), "front" (consumer's) and "middle"
// (the latest published). Publishing swaps back and middle; taking swaps front and middle. The
// swaps are single atomic exchanges with acquire-release ordering, which publishes the slot's
// contents to the other side (ThreadSanitizer-clean).

#include <fieldcast/Frame.h>

#include <array>
#include <atomic>
#include <cstdint>

namespace fieldcast::warp {

/// Single-producer, single-consumer latest-value exchange of T (which may own memory: slots are
/// reused, so after warm-up a Frame of stable size is handed over without allocating).
template <typename T>
class TripleBuffer {
 public:
  TripleBuffer() = default;
  /// Every slot starts as a copy of `initial` (e.g. a frame preallocated at the working size).
  explicit TripleBuffer(const T& initial) : mSlots{initial, initial, initial} {}

  /// The slot the producer fills next. Producer thread only. Wait-free.
  T& back() noexcept { return mSlots[mBack]; }
  /// Makes back() the newest value and hands the producer another slot. Producer thread. Wait-free.
  void publish() noexcept {
    const std::uint8_t old = mMiddle.exchange(static_cast<std::uint8_t>(mBack | kFresh), std::memory_order_acq_rel);
    mBack = old & kIndexMask;
  }

  /// Takes the newest published value if there is one newer than front(); true when it did.
  /// Consumer thread only. Wait-free.
  bool update() noexcept {
    if ((mMiddle.load(std::memory_order_relaxed) & kFresh) == 0) return false;
    const std::uint8_t old = mMiddle.exchange(mFront, std::memory_order_acq_rel);
    mFront = old & kIndexMask;
    mTaken = true;
    return true;
  }
  /// The consumer's current value (stays valid and unchanged until the next update()). Consumer
  /// thread only. The consumer may modify it in place.
  T& front() noexcept { return mSlots[mFront]; }
  const T& front() const noexcept { return mSlots[mFront]; }
  /// True once anything was ever taken by update().
  bool hasTaken() const noexcept { return mTaken; }
  /// update() then front(): the newest complete value. Consumer thread. Wait-free.
  const T& newest() noexcept {
    update();
    return front();
  }

 private:
  static constexpr std::uint8_t kFresh = 0x4;
  static constexpr std::uint8_t kIndexMask = 0x3;

  std::array<T, 3> mSlots{};
  alignas(64) std::atomic<std::uint8_t> mMiddle{1};
  alignas(64) std::uint8_t mBack = 0;   // producer's
  alignas(64) std::uint8_t mFront = 2;  // consumer's
  bool mTaken = false;
};

/// The frame hand-over from the renderer to the PRP.
using FrameHandover = TripleBuffer<Frame>;

}  // namespace fieldcast::warp
