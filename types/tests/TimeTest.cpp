#include <fieldcast/Time.h>

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace fieldcast {
namespace {

TEST(RationalRate, NtscFieldPeriodIsExactOverLongRuns) {
  const RationalRate ntsc{60000, 1001};
  EXPECT_EQ(ntsc.tickOffset(0).count(), 0);
  EXPECT_EQ(ntsc.tickOffset(1).count(), 16'683'333);            // 16 683 333.3 ns
  EXPECT_EQ(ntsc.tickOffset(2).count(), 33'366'667);            // rounds per tick, not accumulated
  EXPECT_EQ(ntsc.tickOffset(60000).count(), 1001'000'000'000);  // exactly 1001 s later
  EXPECT_EQ(ntsc.tickOffset(60000 * 24 * 3600LL).count(), 1001LL * 24 * 3600 * 1'000'000'000);  // a day: no drift
  EXPECT_NEAR(ntsc.hz(), 59.94005994, 1e-8);
}

TEST(RationalRate, IntegerRates) {
  EXPECT_EQ((RationalRate{50, 1}.tickOffset(1).count()), 20'000'000);
  EXPECT_EQ((RationalRate{60, 1}.tickOffset(3).count()), 50'000'000);
}

TEST(Timespec, RoundTrip) {
  const TimePoint t{Nanoseconds{12'345'678'901}};
  const timespec ts = toTimespec(t);
  EXPECT_EQ(ts.tv_sec, 12);
  EXPECT_EQ(ts.tv_nsec, 345'678'901);
  EXPECT_EQ(fromTimespec(ts), t);
  const timespec neg = toTimespec(TimePoint{Nanoseconds{-1}});
  EXPECT_EQ(neg.tv_sec, -1);
  EXPECT_EQ(neg.tv_nsec, 999'999'999);
}

TEST(Seconds, Conversions) {
  EXPECT_EQ(fromSeconds(1.5).count(), 1'500'000'000);
  EXPECT_DOUBLE_EQ(toSeconds(Nanoseconds{250'000'000}), 0.25);
}

TEST(VirtualClock, MovesOnlyWhenTold) {
  VirtualClock clock(TimePoint{Nanoseconds{1000}});
  EXPECT_EQ(clock.now().time_since_epoch().count(), 1000);
  clock.sleepUntil(TimePoint{Nanoseconds{5000}});
  EXPECT_EQ(clock.now().time_since_epoch().count(), 5000);
  clock.sleepUntil(TimePoint{Nanoseconds{10}});  // a past deadline returns at once
  EXPECT_EQ(clock.now().time_since_epoch().count(), 5000);
  clock.advance(Nanoseconds{-7});  // never backwards
  EXPECT_EQ(clock.now().time_since_epoch().count(), 5000);
  clock.advance(Nanoseconds{7});
  EXPECT_EQ(clock.now().time_since_epoch().count(), 5007);
}

TEST(VirtualClock, ConcurrentAdvancesAreAllCounted) {
  VirtualClock clock;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 10000; ++i) clock.advance(Nanoseconds{1});
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(clock.now().time_since_epoch().count(), 40000);
}

TEST(SystemClock, IsMonotonicAndSleepsToAbsoluteDeadlines) {
  SystemClock clock;
  const TimePoint a = clock.now();
  const TimePoint deadline = a + Nanoseconds{2'000'000};
  clock.sleepUntil(deadline);
  EXPECT_GE(clock.now(), deadline);  // never wakes early (no upper bound: machines are noisy)
  clock.sleepUntil(a);               // past deadline: returns
  EXPECT_GE(clock.now(), deadline);
}

}  // namespace
}  // namespace fieldcast
