// The rig's lock figures from two made-up channels whose records differ in known ways.
#include "../LockReport.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

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
    f.hasHostSample = true;
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
  EXPECT_DOUBLE_EQ(r.positionM.max, 0.5);
  EXPECT_EQ(r.sameHostFrame, 17u);
  ASSERT_EQ(r.channels.size(), 2u);
  EXPECT_EQ(r.channels[0].firstField, 10u);
  EXPECT_EQ(r.channels[1].lastField, 31u);
  EXPECT_EQ(r.channels[0].handedOverLate, 0u);
  EXPECT_EQ(r.channels[1].handedOverLate, 1u);
  EXPECT_DOUBLE_EQ(r.channels[1].latestEmissionMs, 5.0);
  EXPECT_TRUE(lockFailures(r).empty());
}

TEST(LockReport, PositionsAreComparedWhereEveryChannelFlewFromTheHost) {
  ChannelRun a = channel("a", 10, 29, 2 * kMs);
  ChannelRun b = channel("b", 10, 29, 2 * kMs);
  // Field 10: the host's first datagram reached a in time, b not yet (b holds its start pose)
  b.fields[10].hasHostSample = false;
  b.fields[10].xM = 5000;
  b.fields[20].yM += 0.25;
  const LockReport r = lockReport({a, b});
  EXPECT_EQ(r.partlyHosted, 1u);
  EXPECT_EQ(r.positionFields, 19u);
  EXPECT_DOUBLE_EQ(r.positionM.max, 0.25);
  // Without a host every field counts
  for (ChannelRun* c : {&a, &b})
    for (auto& [k, f] : c->fields) f.hasHostSample = false;
  EXPECT_DOUBLE_EQ(lockReport({a, b}).positionM.max, 4990.0);
}

TEST(LockReport, FailuresNameWhatBrokeTheLock) {
  ChannelRun a = channel("a", 10, 29, 2 * kMs);
  ChannelRun b = channel("b", 10, 29, 2 * kMs);
  for (auto& [k, f] : b.fields) f.displayNs += 6 * kMs / 10;  // b shows every field 0.6 ms later
  for (std::uint64_t k : {15, 16, 17}) b.fields.erase(k);
  b.summary["fields_missed"] = 3;
  b.summary["fields_emitted"] = 16;  // and one field unaccounted for
  b.summary["lock"]["relocks"] = 1;
  const std::vector<std::string> failures = lockFailures(lockReport({a, b}));
  const auto mentions = [&](const std::string& text) {
    for (const std::string& f : failures)
      if (f.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(mentions("b: 3 fields missed while the host flew"));
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
  EXPECT_EQ(r.channels[0].missed, 1u);
  EXPECT_EQ(r.channels[0].missedInFlight, 0u);  // before field 11, the first made from a host sample
  EXPECT_TRUE(lockFailures(r).empty());         // and the run's count adds up
}

TEST(LockReport, OnlyFieldsMissedWhileTheHostFlewFailTheCheck) {
  // Fields 10..39; the host's first sample reached the channel for field 20. It missed 12 and
  // 13 while the channels were still starting, then 30 and 31 in flight.
  ChannelRun a = channel("a", 10, 39, 2 * kMs);
  for (std::uint64_t k = 10; k < 20; ++k) {
    a.fields[k].hasHostSample = false;
    a.fields[k].hostFrame = -1;
  }
  for (std::uint64_t k : {12, 13, 30, 31}) a.fields.erase(k);
  a.summary["fields_emitted"] = 26;
  a.summary["fields_missed"] = 4;
  const LockReport r = lockReport({a});
  EXPECT_EQ(r.channels[0].flightFirstField, 20u);
  EXPECT_EQ(r.channels[0].missed, 4u);
  EXPECT_EQ(r.channels[0].missedInFlight, 2u);
  EXPECT_EQ(lockFailures(r, 1).size(), 1u);
  EXPECT_TRUE(lockFailures(r, 2).empty());
  // Without a host the whole run is the flight
  for (auto& [k, f] : a.fields) f.hasHostSample = false;
  EXPECT_EQ(lockReport({a}).channels[0].missedInFlight, 4u);
  EXPECT_EQ(lockReport({a}).channels[0].flightFirstField, 10u);
}

TEST(LockReport, FieldsDueWhileTheMachineStalledAreReportedApart) {
  // Missed in flight: 30 and 31 (the probe on CPU 1 stalled from 2 ms before field 30's display
  // time to 20 ms after it), and 36 (no stall then)
  ChannelRun a = channel("a", 10, 39, 2 * kMs);
  for (std::uint64_t k : {30, 31, 36}) a.fields.erase(k);
  a.summary["fields_emitted"] = 27;
  a.summary["fields_missed"] = 3;
  const std::int64_t field30 = 1'000'000'000 + 30 * kPeriodNs;
  const std::vector<MachineStall> stalls = {{1, field30 - 2 * kMs, field30 + 20 * kMs}};
  const LockReport r = lockReport({a}, stalls);
  EXPECT_EQ(r.channels[0].missedInFlight, 3u);
  EXPECT_EQ(r.channels[0].missedInFlightDuringStalls, 2u);
  EXPECT_EQ(r.channels[0].excusedFields, (std::vector<std::uint64_t>{30, 31}));
  EXPECT_EQ(r.machineStalls, 1u);
  EXPECT_DOUBLE_EQ(r.longestStallMs, 22.0);
  EXPECT_EQ(lockFailures(r).size(), 1u);  // field 36
  EXPECT_TRUE(lockFailures(r, 1).empty());
  EXPECT_FALSE(lockFailures(lockReport({a}), 2).empty());  // without the probe all three count
  // A channel whose field thread is pinned to CPU 0 is not excused by CPU 1's stall
  a.fieldCpu = 0;
  EXPECT_EQ(lockReport({a}, stalls).channels[0].missedInFlightDuringStalls, 0u);
  a.fieldCpu = 1;
  EXPECT_EQ(lockReport({a}, stalls).channels[0].missedInFlightDuringStalls, 2u);
}

TEST(LockReport, TheHostsFlightIsTheWindowAndEveryLogMustReachItsEnd) {
  // Missed 12 and 13 before the host's first frame (field 20's display time), 30 and 31 after
  ChannelRun a = channel("a", 10, 39, 2 * kMs);
  for (std::uint64_t k : {12, 13, 30, 31}) a.fields.erase(k);
  a.summary["fields_emitted"] = 26;
  a.summary["fields_missed"] = 4;
  const auto display = [](std::int64_t k) { return 1'000'000'000 + k * kPeriodNs; };
  const LockReport r = lockReport({a}, {}, FlightWindow{display(20), display(38)});
  EXPECT_EQ(r.channels[0].flightFirstField, 20u);
  EXPECT_EQ(r.channels[0].missedInFlight, 2u);
  EXPECT_TRUE(lockFailures(r, 2).empty());
  // Misses straddling the window's ends count only inside it: 13 and 30, not 12 and 31
  EXPECT_EQ(lockReport({a}, {}, FlightWindow{display(13), display(30)}).channels[0].missedInFlight, 2u);
  // The host flew on after the channel's last field: it did not make the whole flight
  const std::vector<std::string> cut = lockFailures(lockReport({a}, {}, FlightWindow{display(20), display(45)}), 2);
  ASSERT_EQ(cut.size(), 1u);
  EXPECT_NE(cut[0].find("a: its field log ends at field 39, before the host's flight ended"), std::string::npos)
      << cut[0];
  // ... or it began before the channel's first field
  const std::vector<std::string> late = lockFailures(lockReport({a}, {}, FlightWindow{display(5), display(38)}), 4);
  ASSERT_EQ(late.size(), 1u);
  EXPECT_NE(late[0].find("a: its field log begins after the host's flight began"), std::string::npos) << late[0];
}

TEST(MachineStalls, AStallExplainsAFieldWhoseLatestStartFallsInItOrAWarpAfter) {
  // A field is missed when its thread has not started it 1 ms before its display time
  const std::vector<MachineStall> stalls = {{0, 100 * kMs, 150 * kMs}};
  EXPECT_EQ(stallAround(stalls, 100 * kMs), &stalls[0]);  // latest start a period before the missed wake-up
  EXPECT_EQ(stallAround(stalls, 161 * kMs), &stalls[0]);  // latest start two warps' time after it woke
  EXPECT_EQ(stallAround(stalls, 162 * kMs), nullptr);
  EXPECT_EQ(stallAround(stalls, 99 * kMs), nullptr);
  EXPECT_EQ(stallAround(stalls, 120 * kMs, 0), &stalls[0]);
  EXPECT_EQ(stallAround(stalls, 120 * kMs, 1), nullptr);  // another CPU's field thread ran on
}

TEST(MachineStalls, TheFieldsAStallMayHaveCostAreCountedOncePerMergedWindow) {
  constexpr std::int64_t kField = 16'683'333;  // 59.94 Hz
  // 100 ms on both CPUs at once: one window of 1 + 100 + 10 ms, seven deadlines
  const std::vector<MachineStall> both = {{0, 100 * kMs, 200 * kMs}, {1, 100 * kMs, 200 * kMs}};
  EXPECT_EQ(fieldsDueInStalls(both, kField), 7);
  // Two stalls of 6 ms far apart: a window of 17 ms each, which may hold two deadlines
  const std::vector<MachineStall> apart = {{0, 100 * kMs, 106 * kMs}, {0, 900 * kMs, 906 * kMs}};
  EXPECT_EQ(fieldsDueInStalls(apart, kField), 4);
  // Overlapping stalls on two CPUs merge into one window (99 .. 230 ms: eight deadlines)
  const std::vector<MachineStall> overlapping = {{0, 100 * kMs, 180 * kMs}, {1, 150 * kMs, 220 * kMs}};
  EXPECT_EQ(fieldsDueInStalls(overlapping, kField), 8);
  EXPECT_EQ(fieldsDueInStalls({}, kField), 0);
}

TEST(MachineStalls, TheTimeStalledBetweenTwoInstantsIsTheMergedWindowsPartInIt) {
  // Windows 99 .. 190 ms and 499 .. 516 ms (a probe period before, two warps' time after)
  const std::vector<MachineStall> stalls = {
      {0, 100 * kMs, 150 * kMs}, {1, 120 * kMs, 180 * kMs}, {0, 500 * kMs, 506 * kMs}};
  EXPECT_EQ(stalledNsBetween(stalls, 0, 1000 * kMs), 91 * kMs + 17 * kMs);
  EXPECT_EQ(stalledNsBetween(stalls, 150 * kMs, 505 * kMs), 40 * kMs + 6 * kMs);
  EXPECT_EQ(stalledNsBetween(stalls, 200 * kMs, 400 * kMs), 0);
  EXPECT_EQ(stalledNsBetween({}, 0, 1000 * kMs), 0);
}

TEST(MachineStalls, AMalformedLineIsNamed) {
  const auto path =
      std::filesystem::temp_directory_path() / ("fieldcast_machine_stalls_test_" + std::to_string(::getpid()) + ".csv");
  writeMachineStalls(path, {{0, 5, 9}, {1, 7, 70}});
  const std::vector<MachineStall> read = readMachineStalls(path);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[1].cpu, 1);
  EXPECT_EQ(read[1].wokeNs, 70);
  {
    std::ofstream out(path, std::ios::app);
    out << "2,90,80\n";  // woke before it was due
  }
  try {
    (void)readMachineStalls(path);
    ADD_FAILURE() << "a stall that ends before it begins was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(":4: expected cpu,due_ns,woke_ns, got 2,90,80"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace fieldcast::tools
