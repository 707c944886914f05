#include <service/Histogram.h>

#include <algorithm>
#include <cmath>

namespace fieldcast::app {
namespace {
const double kLogRatio = std::log(DurationHistogram::kBinRatio);
}

std::size_t DurationHistogram::binOf(double seconds) noexcept {
  if (!(seconds > kMinS)) return 0;
  const double b = std::ceil(std::log(seconds / kMinS) / kLogRatio);
  return std::min(static_cast<std::size_t>(b), kBins - 1);
}

double DurationHistogram::binUpperS(std::size_t bin) noexcept {
  return kMinS * std::pow(kBinRatio, static_cast<double>(bin));
}

void DurationHistogram::record(Nanoseconds d) noexcept {
  const std::int64_t ns = std::max<std::int64_t>(d.count(), 0);
  mBins[binOf(static_cast<double>(ns) * 1e-9)].fetch_add(1, std::memory_order_relaxed);
  mCount.fetch_add(1, std::memory_order_relaxed);
  mSumNs.fetch_add(ns, std::memory_order_relaxed);
  std::int64_t seen = mMaxNs.load(std::memory_order_relaxed);
  while (ns > seen && !mMaxNs.compare_exchange_weak(seen, ns, std::memory_order_relaxed)) {
  }
}

void DurationHistogram::merge(const DurationHistogram& other) noexcept {
  for (std::size_t i = 0; i < kBins; ++i)
    mBins[i].fetch_add(other.mBins[i].load(std::memory_order_relaxed), std::memory_order_relaxed);
  mCount.fetch_add(other.mCount.load(std::memory_order_relaxed), std::memory_order_relaxed);
  mSumNs.fetch_add(other.mSumNs.load(std::memory_order_relaxed), std::memory_order_relaxed);
  const std::int64_t otherMax = other.mMaxNs.load(std::memory_order_relaxed);
  std::int64_t seen = mMaxNs.load(std::memory_order_relaxed);
  while (otherMax > seen && !mMaxNs.compare_exchange_weak(seen, otherMax, std::memory_order_relaxed)) {
  }
}

void DurationHistogram::drainInto(DurationHistogram& out) noexcept {
  for (std::size_t i = 0; i < kBins; ++i)
    out.mBins[i].store(mBins[i].exchange(0, std::memory_order_relaxed), std::memory_order_relaxed);
  out.mCount.store(mCount.exchange(0, std::memory_order_relaxed), std::memory_order_relaxed);
  out.mSumNs.store(mSumNs.exchange(0, std::memory_order_relaxed), std::memory_order_relaxed);
  out.mMaxNs.store(mMaxNs.exchange(0, std::memory_order_relaxed), std::memory_order_relaxed);
}

double DurationHistogram::quantileS(double q) const noexcept {
  // Count from the bins themselves: a record in flight may have bumped mCount but not its bin yet.
  std::uint64_t total = 0;
  for (const auto& b : mBins) total += b.load(std::memory_order_relaxed);
  if (total == 0) return 0.0;
  const auto rank = static_cast<std::uint64_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(total)));
  const double maxS = static_cast<double>(mMaxNs.load(std::memory_order_relaxed)) * 1e-9;
  std::uint64_t seen = 0;
  for (std::size_t i = 0; i < kBins; ++i) {
    seen += mBins[i].load(std::memory_order_relaxed);
    if (seen >= std::max<std::uint64_t>(rank, 1)) return std::min(binUpperS(i), maxS);
  }
  return maxS;
}

DurationSummary DurationHistogram::summary() const noexcept {
  DurationSummary s;
  s.count = mCount.load(std::memory_order_relaxed);
  if (s.count == 0) return s;
  s.p50S = quantileS(0.50);
  s.p99S = quantileS(0.99);
  s.maxS = static_cast<double>(mMaxNs.load(std::memory_order_relaxed)) * 1e-9;
  s.meanS = static_cast<double>(mSumNs.load(std::memory_order_relaxed)) * 1e-9 / static_cast<double>(s.count);
  return s;
}

}  // namespace fieldcast::app
