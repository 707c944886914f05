#pragma once
// The field clock (DESIGN.md §4): field k is shown at t_k = t_0 + k·T. The field thread sleeps to
// absolute wake-up instants (t_k − lead), never relative delays; a field that can no longer be
// made in time is counted as missed and skipped — the schedule goes on, there is never a burst
// to catch up. An external sync edge (GPIO genlock) disciplines t_0 and T; a frame lock shared
// with other channels (lockTo) moves the whole schedule onto their field numbers and epoch.

#include <fieldcast/Field.h>
#include <fieldcast/SeqLock.h>
#include <fieldcast/Time.h>

#include <atomic>
#include <chrono>
#include <cstdint>

namespace fieldcast::warp {

/// Settings of a field clock.
struct FieldClockConfig {
  RationalRate rate{60000, 1001};  ///< fields per second: 60000/1001, 60/1 or 50/1
  ScanMode scan = ScanMode::Interlaced;
  FieldOrder order = FieldOrder::BottomFirst;
  Nanoseconds lead{std::chrono::microseconds(4000)};  ///< wake this long before a field's display time
  /// A field is missed when its work cannot start at least this long before its display time.
  Nanoseconds minWork{std::chrono::microseconds(1000)};
  double syncPhaseGain = 0.25;                           ///< fraction of an edge's phase error corrected per edge
  double syncPeriodGain = 0.1;                           ///< fraction of the period error corrected per edge
  Nanoseconds syncSnap{std::chrono::microseconds(500)};  ///< phase errors beyond this snap at once
  double syncMaxPeriodError = 0.01;  ///< edges implying a period off by more than this fraction are rejected
};

/// One field to make.
struct FieldTick {
  std::uint64_t fieldNumber = 0;  ///< k
  TimePoint displayTime{};        ///< t_k
  TimePoint wakeTime{};           ///< t_k − lead: when the thread was due to start it
  FieldParity parity = FieldParity::Progressive;
  std::uint64_t missedBefore = 0;  ///< fields skipped just before this one
  /// The first field after lockTo moved the schedule: its number does not follow the last one's.
  bool renumbered = false;
};

/// The first field k of the schedule t_k = epoch + k·T (T of `rate`, exact) displayed at `t` or
/// later; 0 when `t` is at or before the epoch. RT-safe.
std::uint64_t firstFieldAtOrAfter(const RationalRate& rate, TimePoint epoch, TimePoint t) noexcept;

/// Throws std::invalid_argument when the rate is not 50, 59.94 (60000/1001) or 60 Hz, or the
/// lead/minWork are negative or longer than a period. `where` prefixes the message.
void validateFieldClockConfig(const FieldClockConfig& config, const char* where = "field clock");

/// The schedule of output fields. next() is called by the field thread only; externalSync() may
/// be called from any one other thread (the GPIO thread).
class FieldClock {
 public:
  /// Field 0 is displayed at `t0`; the first field made is `firstField` (a channel joining a
  /// frame lock late starts at the field the others are at). `clock` must outlive the
  /// FieldClock. Throws on a bad config.
  FieldClock(Clock& clock, const FieldClockConfig& config, TimePoint t0, std::uint64_t firstField = 0);

  /// Sleeps until the wake-up of the next field that can still be made and returns it; fields
  /// whose latest start (t_k − minWork) has passed are skipped and counted as missed. RT-safe.
  FieldTick next() noexcept;

  /// Reports an external sync edge at `edgeTime` (it marks the display time of some field).
  /// Applied by the field thread at its next next(). Wait-free, RT-safe.
  void externalSync(TimePoint edgeTime) noexcept;

  /// Moves the schedule onto another lock's: field 0 displayed at `epoch`, the nominal period.
  /// Applied at the next next(), which goes on with the first field of the new schedule that is
  /// displayed no earlier than the field it would have made, of the same parity (an interlaced
  /// stream keeps its field order); the fields jumped over are not counted as missed. Wait-free,
  /// RT-safe, from any one thread.
  void lockTo(TimePoint epoch) noexcept;

  /// Display time of field k under the current discipline. Field thread. RT-safe.
  TimePoint displayTime(std::uint64_t k) const noexcept;
  /// Parity of field k. RT-safe.
  FieldParity parity(std::uint64_t k) const noexcept { return parityOfField(k, mConfig.scan, mConfig.order); }
  /// Current field period (nominal until an external sync disciplines it). RT-safe.
  Nanoseconds period() const noexcept { return Nanoseconds{(mPeriodQ + kQHalf) >> kQBits}; }

  /// Fields skipped so far (any thread).
  std::uint64_t missedFields() const noexcept { return mMissed.load(std::memory_order_relaxed); }
  /// Sync edges applied and rejected so far (any thread).
  std::uint64_t syncEdgesApplied() const noexcept { return mSyncApplied.load(std::memory_order_relaxed); }
  std::uint64_t syncEdgesRejected() const noexcept { return mSyncRejected.load(std::memory_order_relaxed); }
  /// Times lockTo moved the schedule (any thread).
  std::uint64_t relocks() const noexcept { return mRelocks.load(std::memory_order_relaxed); }
  const FieldClockConfig& config() const noexcept { return mConfig; }

 private:
  // Periods are kept in 1/1024 ns so a disciplined period does not round to whole nanoseconds.
  static constexpr int kQBits = 10;
  static constexpr std::int64_t kQHalf = std::int64_t{1} << (kQBits - 1);

  static std::int64_t nominalPeriodQ(const RationalRate& rate) noexcept;
  void applyPendingSync() noexcept;
  void applyPendingLock() noexcept;
  /// Offset of field anchor + n from the anchor, n ≥ 0.
  Nanoseconds offsetFromAnchor(std::uint64_t n) const noexcept;

  // An instant another thread posts for the field thread: a sync edge, or a frame lock's epoch.
  struct PostedInstant {
    std::int64_t timeNs = 0;
    std::uint64_t sequence = 0;
  };

  Clock& mClock;
  FieldClockConfig mConfig;
  // Schedule: t_k = mAnchorTime + offset(k − mAnchorField). Exact rational until disciplined.
  std::uint64_t mAnchorField = 0;
  TimePoint mAnchorTime{};
  bool mDisciplined = false;
  std::int64_t mPeriodQ = 0;  // period in 1/1024 ns
  std::uint64_t mNextField = 0;
  // Sync edges: posted by another thread, consumed here.
  SeqLock<PostedInstant> mPendingEdge;
  std::uint64_t mEdgeSequence = 0;   // writer side
  std::uint64_t mEdgesConsumed = 0;  // field-thread side
  bool mHavePreviousEdge = false;
  TimePoint mPreviousEdge{};
  std::uint64_t mPreviousEdgeField = 0;
  // Frame lock: an epoch posted by lockTo, consumed here.
  SeqLock<PostedInstant> mPendingLock;
  std::uint64_t mLockSequence = 0;   // writer side
  std::uint64_t mLocksConsumed = 0;  // field-thread side
  bool mRenumbered = false;          // the next tick is the first after a move
  std::atomic<std::uint64_t> mMissed{0};
  std::atomic<std::uint64_t> mSyncApplied{0};
  std::atomic<std::uint64_t> mSyncRejected{0};
  std::atomic<std::uint64_t> mRelocks{0};
};

}  // namespace fieldcast::warp
