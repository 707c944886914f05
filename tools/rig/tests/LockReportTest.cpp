// The rig's lock figures from two made-up channels whose records differ in known ways.
#include "../LockReport.h"

#include <gtest/gtest.h>

namespace fieldcast::tools {
namespace {

constexpr std::int64_t kPeriodNs = 16'683'350;
constexpr std::int64_t kMs = 1'000'000;

// Fields first..last (inclusive): shown on the one schedule, handed over `early` before it.
ChannelRun channel(const std::string& name, std::uint64_t first, std::uint64_t last, std::int64_t earlyNs) {
  ChannelRun c;
  c.name = name;
  for (std::uint64_t k = first; k <= last; ++k) {
    LoggedField f;
    f.displayNs = 1'000'000'000 + static_cast<std::int64_t>(k) * kPeriodNs;
    f.emittedNs = f.displayNs - earlyNs;
    f.xM = static_cast<double>(k);
    f.hostFrame = static_cast<std::int64_t>(k / 2);
    c.fields[k] = f;
  }
  c.summary = {{"fields_emitted", last - first + 1},
               {"fields_missed", 0},
               {"fields_black", 0},
               {"lock", {{"relocks", 0}, {"first_field", first}}}};
  return c;
}

TEST(LockReport, SpreadsAreAcrossTheFieldsEveryChannelMade) {
  ChannelRun a = channel("a", 10, 29, 2 * kMs);
  ChannelRun b = channel("b", 12, 31, 1 * kMs);
  b.fields[20].emittedNs = b.fields[20].displayNs + 5 * kMs;  // handed over 5 ms late
  b.fields[21].xM += 0.5;                                     // another instant's position
  b.fields[22].hostFrame = 999;                               // made from another host sample
  const LockReport r = lockReport({a, b});
  EXPECT_EQ(r.commonFields, 18u);  // 12..29
  EXPECT_EQ(r.displayMs.max, 0.0);
  EXPECT_DOUBLE_EQ(r.emittedMs.p50, 1.0);
  EXPECT_DOUBLE_EQ(r.emittedMs.max, 7.0);
  EXPECT_DOUBLE_EQ(r.positionSpreadMaxM, 0.5);
  EXPECT_EQ(r.sameHostFrame, 17u);
  ASSERT_EQ(r.channels.size(), 2u);
  EXPECT_EQ(r.channels[0].firstField, 10u);
  EXPECT_EQ(r.channels[1].lastField, 31u);
  EXPECT_EQ(r.channels[0].handedOverLate, 0u);
  EXPECT_EQ(r.channels[1].handedOverLate, 1u);
  EXPECT_DOUBLE_EQ(r.channels[1].latestEmissionMs, 5.0);
  EXPECT_TRUE(lockFailures(r).empty());
}

TEST(LockReport, FailuresNameWhatBrokeTheLock) {
  ChannelRun a = channel("a", 10, 29, 2 * kMs);
  ChannelRun b = channel("b", 10, 29, 2 * kMs);
  for (auto& [k, f] : b.fields) f.displayNs += 6 * kMs / 10;  // b shows every field 0.6 ms later
  b.summary["fields_missed"] = 3;
  b.summary["fields_emitted"] = 16;  // and one field unaccounted for
  b.summary["lock"]["relocks"] = 1;
  const std::vector<std::string> failures = lockFailures(lockReport({a, b}));
  const auto mentions = [&](const std::string& text) {
    for (const std::string& f : failures)
      if (f.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(mentions("b: 3 fields missed"));
  EXPECT_TRUE(mentions("b: moved onto another lock 1 times"));
  EXPECT_TRUE(mentions("display times of field k spread 0.6"));
  EXPECT_TRUE(mentions("b: 16 fields emitted between field 10 and 29"));  // 16 + 3 missed ≠ 20
  EXPECT_FALSE(mentions("a:"));
  // A shared machine's allowance covers the missed fields, nothing else
  const std::vector<std::string> allowed = lockFailures(lockReport({a, b}), 3);
  EXPECT_EQ(allowed.size(), failures.size() - 1);
  EXPECT_TRUE(lockFailures(lockReport({a, channel("c", 40, 50, 0)})).size() == 1);  // nothing in common
}

TEST(LockReport, AMissedFirstFieldIsStillInTheChannelsRun) {
  // The channel planned field 10 but missed it: its log starts at 11, its summary says so
  ChannelRun a = channel("a", 10, 29, 2 * kMs);
  a.fields.erase(10);
  a.summary["fields_emitted"] = 19;
  a.summary["fields_missed"] = 1;
  const LockReport r = lockReport({a});
  EXPECT_EQ(r.channels[0].firstField, 10u);
  EXPECT_TRUE(lockFailures(r, 1).empty());
}

}  // namespace
}  // namespace fieldcast::tools
