#include <io_bridge/ExternalSync.h>

#include <cmath>

namespace fieldcast::io {

ExternalSyncEstimator::ExternalSyncEstimator(RationalRate nominal, double tolerance) noexcept
    : mNominalNs(1e9 * static_cast<double>(nominal.denominator) / static_cast<double>(nominal.numerator)),
      mTolerance(tolerance) {
  mEstimate.periodNs = mNominalNs;
}

void ExternalSyncEstimator::onPulse(TimePoint t) noexcept {
  const std::int64_t tNs = t.time_since_epoch().count();
  const double period = mEstimate.periodNs;
  if (mCount > 0) {
    const double gap = static_cast<double>(tNs - mLastTimeNs);
    const double periods = gap / period;
    const double whole = std::round(periods);
    if (whole < 1.0) {  // closer than half a period: a glitch or contact bounce
      ++mEstimate.glitches;
      return;
    }
    if (whole > 16.0 || std::abs(periods - whole) > mTolerance) {
      // A long outage or a pulse far off the grid: start over from this pulse.
      mCount = 0;
      mHead = 0;
      mEstimate.locked = false;
    } else {
      mEstimate.missed += static_cast<std::uint64_t>(whole) - 1;
      mLastIndex += static_cast<std::int64_t>(whole);
    }
  }
  if (mCount == 0) mLastIndex = 0;
  mLastTimeNs = tNs;
  mIndex[mHead] = mLastIndex;
  mTimeNs[mHead] = tNs;
  mHead = (mHead + 1) % kWindow;
  if (mCount < kWindow) ++mCount;
  ++mEstimate.pulses;
  fit();
}

void ExternalSyncEstimator::fit() noexcept {
  if (mCount < 2) {
    mEstimate.lastPulse = TimePoint{Nanoseconds{mLastTimeNs}};
    return;
  }
  // Least squares t = a + b·k, relative to the newest pulse so the doubles stay small.
  double sk = 0, st = 0, skk = 0, skt = 0;
  const auto n = static_cast<double>(mCount);
  for (std::size_t i = 0; i < mCount; ++i) {
    const double k = static_cast<double>(mIndex[i] - mLastIndex);
    const double tt = static_cast<double>(mTimeNs[i] - mLastTimeNs);
    sk += k;
    st += tt;
    skk += k * k;
    skt += k * tt;
  }
  const double denom = n * skk - sk * sk;
  if (denom <= 0.0) return;
  const double b = (n * skt - sk * st) / denom;
  const double a = (st - b * sk) / n;  // fitted time of index mLastIndex, relative to mLastTimeNs
  double ss = 0;
  for (std::size_t i = 0; i < mCount; ++i) {
    const double k = static_cast<double>(mIndex[i] - mLastIndex);
    const double r = static_cast<double>(mTimeNs[i] - mLastTimeNs) - (a + b * k);
    ss += r * r;
  }
  mEstimate.periodNs = b;
  mEstimate.jitterRmsNs = std::sqrt(ss / n);
  mEstimate.lastPulse = TimePoint{Nanoseconds{mLastTimeNs + static_cast<std::int64_t>(std::llround(a))}};
  mEstimate.locked = mCount >= 8 && mEstimate.jitterRmsNs < 0.05 * b;
}

}  // namespace fieldcast::io
