#include <service/Histogram.h>

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace fieldcast::app {
namespace {

Nanoseconds us(double micro) { return Nanoseconds{static_cast<std::int64_t>(micro * 1000.0)}; }

TEST(DurationHistogram, PercentilesWithinOneBin) {
  DurationHistogram h;
  for (int i = 1; i <= 1000; ++i) h.record(us(i * 10.0));  // 10 µs … 10 ms, uniform
  const DurationSummary s = h.summary();
  EXPECT_EQ(s.count, 1000u);
  EXPECT_NEAR(s.p50S, 5e-3, 5e-3 * 0.021);
  EXPECT_NEAR(s.p99S, 9.9e-3, 9.9e-3 * 0.021);
  EXPECT_DOUBLE_EQ(s.maxS, 10e-3);
  EXPECT_NEAR(s.meanS, 5.005e-3, 1e-9);
}

TEST(DurationHistogram, EmptyAndTinyAndHuge) {
  DurationHistogram h;
  EXPECT_EQ(h.summary().count, 0u);
  EXPECT_EQ(h.quantileS(0.5), 0.0);
  h.record(Nanoseconds{0});
  h.record(Nanoseconds{-5});  // clock skew: treated as zero, never a bad bin
  h.record(Nanoseconds{5'000'000'000'000});
  EXPECT_EQ(h.count(), 3u);
  EXPECT_EQ(DurationHistogram::binOf(1e9), DurationHistogram::kBins - 1);
}

TEST(DurationHistogram, DrainMovesEverythingAndMergeAdds) {
  DurationHistogram live, window, total;
  for (int i = 0; i < 100; ++i) live.record(us(100));
  live.drainInto(window);
  EXPECT_EQ(live.count(), 0u);
  EXPECT_EQ(window.count(), 100u);
  total.merge(window);
  total.merge(window);
  EXPECT_EQ(total.count(), 200u);
  EXPECT_NEAR(total.summary().p50S, 100e-6, 100e-6 * 0.021);
}

TEST(DurationHistogram, ConcurrentRecordsAreAllCounted) {
  DurationHistogram h;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&h, t] {
      for (int i = 0; i < 20000; ++i) h.record(us(1 + t));
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(h.count(), 80000u);
  EXPECT_DOUBLE_EQ(h.summary().maxS, 4e-6);
}

}  // namespace
}  // namespace fieldcast::app
