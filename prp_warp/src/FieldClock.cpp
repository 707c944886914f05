// Field scheduling on absolute deadlines, with a second-order discipline (phase and period) to
// an external sync edge, as a genlock would do.
#include <prp_warp/FieldClock.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fieldcast::warp {

void validateFieldClockConfig(const FieldClockConfig& c, const char* where) {
  const bool rateOk = (c.rate.numerator == 60000 && c.rate.denominator == 1001) ||
                      (c.rate.numerator == 60 && c.rate.denominator == 1) ||
                      (c.rate.numerator == 50 && c.rate.denominator == 1);
  if (!rateOk) {
    throw std::invalid_argument(std::string(where) + ": rate: expected 50, 59.94 or 60 Hz, got " +
                                std::to_string(c.rate.hz()));
  }
  const Nanoseconds period = c.rate.period();
  if (c.lead.count() < 0 || c.lead >= period) {
    throw std::invalid_argument(std::string(where) + ": lead: expected 0 to one field period (" +
                                std::to_string(period.count()) + " ns), got " + std::to_string(c.lead.count()) + " ns");
  }
  if (c.minWork.count() < 0 || c.minWork > c.lead) {
    throw std::invalid_argument(std::string(where) + ": min_work: expected 0 to lead, got " +
                                std::to_string(c.minWork.count()) + " ns");
  }
  if (!(c.syncPhaseGain > 0.0 && c.syncPhaseGain <= 1.0) || !(c.syncPeriodGain >= 0.0 && c.syncPeriodGain <= 1.0)) {
    throw std::invalid_argument(std::string(where) + ": sync gains: expected phase in (0, 1] and period in [0, 1]");
  }
}

std::uint64_t firstFieldAtOrAfter(const RationalRate& rate, TimePoint epoch, TimePoint t) noexcept {
  if (t <= epoch) return 0;
  const auto at = [&](std::uint64_t k) { return epoch + rate.tickOffset(static_cast<std::int64_t>(k)); };
  // The estimate in doubles is within a field of the answer; step to it exactly
  const double periods = static_cast<double>((t - epoch).count()) / static_cast<double>(rate.period().count());
  auto k = static_cast<std::uint64_t>(std::max(0.0, std::floor(periods)));
  while (k > 0 && at(k - 1) >= t) --k;
  while (at(k) < t) ++k;
  return k;
}

std::int64_t FieldClock::nominalPeriodQ(const RationalRate& rate) noexcept {
  // Exact to the rounding of one 1/1024 ns
  return (rate.denominator * 1'000'000'000LL * (1LL << kQBits) + rate.numerator / 2) / rate.numerator;
}

FieldClock::FieldClock(Clock& clock, const FieldClockConfig& config, TimePoint t0, std::uint64_t firstField)
    : mClock(clock), mConfig(config), mAnchorTime(t0), mNextField(firstField) {
  validateFieldClockConfig(config);
  mPeriodQ = nominalPeriodQ(config.rate);
}

Nanoseconds FieldClock::offsetFromAnchor(std::uint64_t n) const noexcept {
  if (!mDisciplined) return mConfig.rate.tickOffset(static_cast<std::int64_t>(n));
  // n · period in 1/1024 ns passes 2^63 after 2^53 ns (104 days) at any rate: split n at 1024,
  // whose share is a whole number of nanoseconds, so the sum is the same rounding, exact to far
  // beyond any run
  constexpr std::uint64_t kWhole = std::uint64_t{1} << kQBits;
  const auto wholeNs = static_cast<std::int64_t>(n / kWhole) * mPeriodQ;
  const auto restQ = static_cast<std::int64_t>(n % kWhole) * mPeriodQ;
  return Nanoseconds{wholeNs + ((restQ + kQHalf) >> kQBits)};
}

TimePoint FieldClock::displayTime(std::uint64_t k) const noexcept {
  if (k >= mAnchorField) return mAnchorTime + offsetFromAnchor(k - mAnchorField);
  return mAnchorTime - offsetFromAnchor(mAnchorField - k);
}

void FieldClock::externalSync(TimePoint edgeTime) noexcept {
  mPendingEdge.store(PostedInstant{edgeTime.time_since_epoch().count(), ++mEdgeSequence});
}

void FieldClock::applyPendingSync() noexcept {
  const PostedInstant edge = mPendingEdge.load();
  if (edge.sequence == mEdgesConsumed) return;
  mEdgesConsumed = edge.sequence;
  const TimePoint e{Nanoseconds{edge.timeNs}};

  // The field the edge belongs to: the one whose display time is nearest
  const double periodNs = static_cast<double>(mPeriodQ) / (1 << kQBits);
  const double fieldsFromAnchor = static_cast<double>((e - mAnchorTime).count()) / periodNs;
  const std::int64_t kSigned = static_cast<std::int64_t>(mAnchorField) + std::llround(fieldsFromAnchor);
  if (kSigned < 0) {
    mSyncRejected.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  const auto k = static_cast<std::uint64_t>(kSigned);

  // Period: from the interval to the previous edge, low-passed; a glitch is rejected
  if (mHavePreviousEdge && k > mPreviousEdgeField) {
    const double measuredNs =
        static_cast<double>((e - mPreviousEdge).count()) / static_cast<double>(k - mPreviousEdgeField);
    if (std::abs(measuredNs - periodNs) > mConfig.syncMaxPeriodError * periodNs) {
      mSyncRejected.fetch_add(1, std::memory_order_relaxed);
      mPreviousEdge = e;
      mPreviousEdgeField = k;
      return;
    }
    mPeriodQ += std::llround(mConfig.syncPeriodGain * (measuredNs - periodNs) * (1 << kQBits));
  }

  // Phase: snap when far off (first lock), otherwise correct a fraction of the error
  const Nanoseconds error = e - displayTime(k);
  const bool snap = !mHavePreviousEdge || error > mConfig.syncSnap || error < -mConfig.syncSnap;
  const Nanoseconds correction =
      snap ? error : Nanoseconds{std::llround(mConfig.syncPhaseGain * static_cast<double>(error.count()))};
  mAnchorTime = displayTime(k) + correction;
  mAnchorField = k;
  mDisciplined = true;
  mHavePreviousEdge = true;
  mPreviousEdge = e;
  mPreviousEdgeField = k;
  mSyncApplied.fetch_add(1, std::memory_order_relaxed);
}

void FieldClock::lockTo(TimePoint epoch) noexcept {
  mPendingLock.store(PostedInstant{epoch.time_since_epoch().count(), ++mLockSequence});
}

void FieldClock::applyPendingLock() noexcept {
  const PostedInstant lock = mPendingLock.load();
  if (lock.sequence == mLocksConsumed) return;
  mLocksConsumed = lock.sequence;
  const TimePoint epoch{Nanoseconds{lock.timeNs}};
  const TimePoint due = displayTime(mNextField);  // what the old schedule would show next
  mAnchorField = 0;
  mAnchorTime = epoch;
  mDisciplined = false;
  mPeriodQ = nominalPeriodQ(mConfig.rate);
  // The first field of the new schedule displayed at `due` or later, of the same parity when
  // interlaced
  std::uint64_t k = firstFieldAtOrAfter(mConfig.rate, epoch, due);
  if (mConfig.scan == ScanMode::Interlaced && (k & 1U) != (mNextField & 1U)) ++k;
  mNextField = k;
  mRenumbered = true;
  mRelocks.fetch_add(1, std::memory_order_relaxed);
}

FieldTick FieldClock::next() noexcept {
  applyPendingLock();
  applyPendingSync();
  std::uint64_t k = mNextField;
  // Skip what can no longer be made: one field late is one field missed, never a burst
  const TimePoint now = mClock.now();
  std::uint64_t missed = 0;
  if (now > displayTime(k) - mConfig.minWork) {
    // Jump close to the first feasible field at once (after a long stall), then step exactly
    const auto behind =
        (now - (displayTime(k) - mConfig.minWork)).count() / std::max<std::int64_t>(period().count(), 1);
    if (behind > 1) {
      k += static_cast<std::uint64_t>(behind - 1);
      missed += static_cast<std::uint64_t>(behind - 1);
    }
  }
  while (now > displayTime(k) - mConfig.minWork) {
    ++k;
    ++missed;
  }
  if (missed) mMissed.fetch_add(missed, std::memory_order_relaxed);
  FieldTick tick;
  tick.fieldNumber = k;
  tick.displayTime = displayTime(k);
  tick.wakeTime = tick.displayTime - mConfig.lead;
  tick.parity = parity(k);
  tick.missedBefore = missed;
  tick.renumbered = mRenumbered;
  mRenumbered = false;
  mClock.sleepUntil(tick.wakeTime);
  mNextField = k + 1;
  return tick;
}

}  // namespace fieldcast::warp
