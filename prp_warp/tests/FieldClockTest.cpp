// The field clock in virtual time: exact deadlines, missed fields without bursts, external sync.
#include <prp_warp/FieldClock.h>

#include <gtest/gtest.h>

namespace fieldcast::warp {
namespace {

using std::chrono::microseconds;
using std::chrono::milliseconds;

const TimePoint kT0{Nanoseconds{5'000'000'000}};

TEST(FieldClock, SleepsToExactAbsoluteDeadlines) {
  VirtualClock clock(kT0 - milliseconds(100));
  FieldClockConfig cfg;  // 59.94 Hz interlaced, lead 4 ms
  FieldClock fc(clock, cfg, kT0);
  const RationalRate ntsc{60000, 1001};
  for (std::uint64_t k = 0; k < 200; ++k) {
    const FieldTick tick = fc.next();
    ASSERT_EQ(tick.fieldNumber, k);
    ASSERT_EQ(tick.displayTime, kT0 + ntsc.tickOffset(static_cast<std::int64_t>(k)));
    ASSERT_EQ(tick.wakeTime, tick.displayTime - cfg.lead);
    ASSERT_EQ(clock.now(), tick.wakeTime);  // slept exactly to the absolute wake-up
    ASSERT_EQ(tick.missedBefore, 0u);
    clock.advance(microseconds(1500));  // the field's work
  }
  EXPECT_EQ(fc.missedFields(), 0u);
  // No drift: field 60000 is exactly 1001 s after field 0
  EXPECT_EQ(fc.displayTime(60000) - kT0, Nanoseconds{1001'000'000'000});
}

TEST(FieldClock, ProgressiveFiftyHertzHasOneFieldPerPeriod) {
  VirtualClock clock(kT0 - milliseconds(100));
  FieldClockConfig cfg;
  cfg.rate = {50, 1};
  cfg.scan = ScanMode::Progressive;
  FieldClock fc(clock, cfg, kT0);
  for (int k = 0; k < 10; ++k) {
    const FieldTick t = fc.next();
    EXPECT_EQ(t.parity, FieldParity::Progressive);
    EXPECT_EQ(t.displayTime, kT0 + milliseconds(20 * k));
  }
}

TEST(FieldClock, LateWorkCountsMissedFieldsAndNeverBursts) {
  VirtualClock clock(kT0 - milliseconds(100));
  FieldClockConfig cfg;
  cfg.rate = {60, 1};
  FieldClock fc(clock, cfg, kT0);
  const Nanoseconds period = cfg.rate.period();
  fc.next();  // field 0
  fc.next();  // field 1
  // A stall of three periods during field 1's work
  clock.advance(3 * period);
  const FieldTick late = fc.next();
  EXPECT_GT(late.fieldNumber, 2u);
  EXPECT_EQ(late.missedBefore, late.fieldNumber - 2);
  EXPECT_EQ(fc.missedFields(), late.missedBefore);
  // The field returned can still be made: its latest start is not past
  EXPECT_LE(clock.now(), late.displayTime - cfg.minWork);
  // The schedule continues one period at a time: no catch-up burst
  TimePoint previousWake = late.wakeTime;
  for (int i = 0; i < 5; ++i) {
    const FieldTick t = fc.next();
    EXPECT_EQ(t.fieldNumber, late.fieldNumber + 1 + static_cast<std::uint64_t>(i));
    EXPECT_EQ(t.missedBefore, 0u);
    EXPECT_GE(t.wakeTime - previousWake, period - Nanoseconds{1});
    EXPECT_EQ(clock.now(), t.wakeTime);
    previousWake = t.wakeTime;
  }
  // Work that overran only into the lead still makes its field (returned at once, not skipped)
  clock.advance(period + microseconds(500));
  const FieldTick tight = fc.next();
  EXPECT_EQ(tight.missedBefore, 0u);
  EXPECT_GT(clock.now(), tight.wakeTime);
}

TEST(FieldClock, AVeryLongStallSkipsWithoutLooping) {
  VirtualClock clock(kT0);
  FieldClock fc(clock, FieldClockConfig{}, kT0 + milliseconds(10));
  clock.advance(std::chrono::hours(10));
  const FieldTick t = fc.next();
  EXPECT_NEAR(static_cast<double>(t.missedBefore), 10 * 3600 * 59.94, 2.0);
  EXPECT_LE(clock.now(), t.displayTime - FieldClockConfig{}.minWork);
}

TEST(FieldClock, ExternalSyncLocksPhaseAndPeriodToTheEdges) {
  VirtualClock clock(kT0 - milliseconds(50));
  FieldClockConfig cfg;  // nominal 59.94 Hz …
  FieldClock fc(clock, cfg, kT0);
  // … but the house sync runs at exactly 60 Hz, 3 ms after our field 0
  const Nanoseconds housePeriod{16'666'667};
  const TimePoint firstEdge = kT0 + milliseconds(3);
  std::uint64_t edges = 0;
  FieldTick tick{};
  for (int i = 0; i < 400; ++i) {
    tick = fc.next();
    // The edge of each field arrives at its display time on the house clock
    const TimePoint edge = firstEdge + housePeriod * static_cast<std::int64_t>(tick.fieldNumber);
    clock.advanceTo(edge);
    fc.externalSync(edge);
    ++edges;
  }
  // Locked: the next display times fall on the house edges and the period is the house period
  const std::uint64_t k = tick.fieldNumber + 1;
  const FieldTick next = fc.next();  // applies the last edge
  EXPECT_EQ(next.fieldNumber, k);
  EXPECT_EQ(fc.syncEdgesApplied(), edges);
  EXPECT_EQ(fc.syncEdgesRejected(), 0u);
  const TimePoint houseEdge = firstEdge + housePeriod * static_cast<std::int64_t>(k);
  EXPECT_LT(std::abs((next.displayTime - houseEdge).count()), 2'000);  // within 2 µs
  EXPECT_LT(std::abs((fc.period() - housePeriod).count()), 2);
  EXPECT_EQ(fc.missedFields(), 0u);
}

// Disciplined by the edges, then none applied for months (the sync lost, or every edge
// rejected): display times still run on at the field period. n · period in 1/1024 ns overflowed
// 64 bits after 104 days, and the field loop then skipped fields forever.
TEST(FieldClock, ADisciplinedClockRunsOnForMonthsWithoutAnEdge) {
  VirtualClock clock(kT0 - milliseconds(50));
  FieldClock fc(clock, FieldClockConfig{}, kT0);
  const Nanoseconds period = FieldClockConfig{}.rate.period();
  fc.next();
  fc.externalSync(kT0);
  fc.next();  // applies it: the clock is disciplined from here
  EXPECT_EQ(fc.syncEdgesApplied(), 1u);
  const auto fieldsIn = [&](double days) { return static_cast<std::uint64_t>(days * 86400.0 * 59.94); };
  for (const double days : {1.0, 103.0, 105.0, 200.0, 3650.0}) {
    const std::uint64_t k = fieldsIn(days);
    const Nanoseconds step = fc.displayTime(k + 1) - fc.displayTime(k);
    EXPECT_LE(std::abs((step - period).count()), 1) << days << " days";
    // Against the nominal schedule, exact in integers: off by no more than the disciplined period's
    // rounding to 1/1024 ns, half of that a field
    const Nanoseconds drift =
        fc.displayTime(k) - (kT0 + FieldClockConfig{}.rate.tickOffset(static_cast<std::int64_t>(k)));
    EXPECT_LE(static_cast<double>(std::abs(drift.count())), static_cast<double>(k) / 2048.0 + 2.0) << days << " days";
  }
  clock.advanceTo(fc.displayTime(fieldsIn(120.0)));  // the loop's next field, 120 days on
  const FieldTick t = fc.next();
  EXPECT_GT(t.displayTime, clock.now());
  EXPECT_LT(t.displayTime - clock.now(), 2 * period);
}

TEST(FieldClock, ASyncGlitchIsRejected) {
  VirtualClock clock(kT0 - milliseconds(50));
  FieldClock fc(clock, FieldClockConfig{}, kT0);
  const Nanoseconds period = FieldClockConfig{}.rate.period();
  fc.next();
  fc.externalSync(kT0);
  fc.next();
  fc.externalSync(kT0 + period);
  fc.next();
  // An edge 5 ms early on the third field implies a 30 % shorter period: rejected
  fc.externalSync(kT0 + 2 * period - milliseconds(5));
  fc.next();
  EXPECT_EQ(fc.syncEdgesApplied(), 2u);
  EXPECT_EQ(fc.syncEdgesRejected(), 1u);
  EXPECT_LE(std::abs((fc.displayTime(3) - (kT0 + 3 * period)).count()), 2);
}

TEST(FieldClock, AChannelJoiningLateStartsAtTheLocksFieldNumber) {
  // Field 0 was displayed 10 s ago (another channel's epoch); this one starts at field 600.
  VirtualClock clock(kT0 + std::chrono::seconds(10) - milliseconds(50));
  FieldClockConfig cfg;
  cfg.rate = {60, 1};
  FieldClock fc(clock, cfg, kT0, 600);
  for (std::uint64_t k = 600; k < 610; ++k) {
    const FieldTick tick = fc.next();
    ASSERT_EQ(tick.fieldNumber, k);
    ASSERT_EQ(tick.displayTime, kT0 + cfg.rate.tickOffset(static_cast<std::int64_t>(k)));
    ASSERT_EQ(tick.missedBefore, 0u);
  }
}

TEST(FieldClock, LockingToAnotherEpochTakesItsFieldNumbersAndKeepsTheFieldOrder) {
  VirtualClock clock(kT0 - milliseconds(50));
  FieldClockConfig cfg;  // 59.94 Hz interlaced
  FieldClock fc(clock, cfg, kT0);
  for (int k = 0; k < 5; ++k) fc.next();  // fields 0–4; field 5 (top, odd) would come next
  const TimePoint due = fc.displayTime(5);
  // The other channels' field 0 was 1000.3 fields before ours
  const Nanoseconds period = cfg.rate.period();
  const TimePoint epoch = kT0 - 1000 * period - period * 3 / 10;
  fc.lockTo(epoch);
  const FieldTick tick = fc.next();
  // Their schedule's first field displayed at or after `due` is 1006 (at due + 0.7 periods), but
  // field 5 is odd: 1007 keeps the interlaced order.
  EXPECT_EQ(tick.fieldNumber, 1007u);
  EXPECT_EQ(tick.displayTime, epoch + cfg.rate.tickOffset(1007));
  EXPECT_GE(tick.displayTime, due);
  EXPECT_EQ(tick.parity, fc.parity(5));
  EXPECT_EQ(tick.missedBefore, 0u);
  EXPECT_TRUE(tick.renumbered);
  EXPECT_EQ(fc.relocks(), 1u);
  EXPECT_EQ(fc.missedFields(), 0u);
  // and the schedule goes on on theirs
  const FieldTick after = fc.next();
  EXPECT_EQ(after.displayTime, epoch + cfg.rate.tickOffset(1008));
  EXPECT_FALSE(after.renumbered);
}

TEST(FieldClock, RejectsBadConfiguration) {
  VirtualClock clock;
  FieldClockConfig bad;
  bad.rate = {61, 1};
  EXPECT_THROW(FieldClock(clock, bad, kT0), std::invalid_argument);
  FieldClockConfig longLead;
  longLead.lead = milliseconds(20);
  EXPECT_THROW(FieldClock(clock, longLead, kT0), std::invalid_argument);
  try {
    validateFieldClockConfig(bad, "config/fieldcast.toml: output");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("expected 50, 59.94 or 60"), std::string::npos);
  }
}

}  // namespace
}  // namespace fieldcast::warp
