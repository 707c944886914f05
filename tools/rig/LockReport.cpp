// The rig's lock figures from the channels' field logs and summaries.
#include "LockReport.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <sstream>

namespace fieldcast::tools {
namespace {

Spread spreadOf(std::vector<double> values) {
  Spread s;
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  const auto at = [&](double q) {
    return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
  };
  s.p50 = at(0.5);
  s.p99 = at(0.99);
  s.max = values.back();
  return s;
}

struct MissedFields {
  std::uint64_t inFlight = 0;
  std::vector<std::uint64_t> duringStalls;  ///< their numbers
};

// The field numbers missing from a log between logged fields, those displayed in [begin, end],
// and of those the ones a machine stall explains; a missing field's display time lies on the
// line between its neighbours'. A gap wider than the channel's missed fields (a jump onto
// another lock) or without time between its ends is not a run of misses.
MissedFields missedFields(const std::map<std::uint64_t, LoggedField>& fields, std::int64_t begin, std::int64_t end,
                          const std::vector<MachineStall>& stalls, int cpu, std::uint64_t missed) {
  MissedFields m;
  if (fields.empty()) return m;
  for (auto before = fields.begin(), after = std::next(before); after != fields.end(); before = after++) {
    const std::uint64_t gap = after->first - before->first;
    const std::int64_t spanNs = after->second.displayNs - before->second.displayNs;
    if (gap < 2 || gap - 1 > missed || spanNs <= 0) continue;
    for (std::uint64_t k = 1; k < gap; ++k) {
      const std::int64_t displayNs =
          before->second.displayNs + spanNs / static_cast<std::int64_t>(gap) * static_cast<std::int64_t>(k);
      if (displayNs < begin || displayNs > end) continue;
      ++m.inFlight;
      if (stallAround(stalls, displayNs, cpu) != nullptr) m.duringStalls.push_back(before->first + k);
    }
  }
  return m;
}

nlohmann::json toJson(const Spread& s) { return {{"p50", s.p50}, {"p99", s.p99}, {"max", s.max}}; }

}  // namespace

LockReport lockReport(const std::vector<ChannelRun>& channels, const std::vector<MachineStall>& stalls,
                      std::optional<FlightWindow> flight) {
  LockReport r;
  r.machineStalls = stalls.size();
  for (const MachineStall& s : stalls) r.longestStallMs = std::max(r.longestStallMs, s.lateMs());
  r.flight = flight;
  for (const ChannelRun& c : channels) {
    LockReport::PerChannel p;
    p.name = c.name;
    p.fieldCpu = c.fieldCpu;
    p.fields = c.summary.value("fields_emitted", std::uint64_t{0});
    p.missed = c.summary.value("fields_missed", std::uint64_t{0});
    p.black = c.summary.value("fields_black", std::uint64_t{0});
    if (c.summary.contains("lock")) p.relocks = c.summary["lock"].value("relocks", std::uint64_t{0});
    p.missedInFlight = p.missed;  // without a log, every miss counts
    if (!c.fields.empty()) {
      // The first field planned (a missed first field is not in the log)
      p.firstField = c.summary.contains("lock") ? c.summary["lock"].value("first_field", c.fields.begin()->first)
                                                : c.fields.begin()->first;
      p.lastField = c.fields.rbegin()->first;
      p.firstDisplayNs = c.fields.begin()->second.displayNs;
      p.lastDisplayNs = c.fields.rbegin()->second.displayNs;
      // The flight: the host's own instants; without them, from the first field made from a
      // host sample; without a host, the whole run
      std::int64_t begin = std::numeric_limits<std::int64_t>::min();
      std::int64_t end = std::numeric_limits<std::int64_t>::max();
      const auto hosted =
          std::find_if(c.fields.begin(), c.fields.end(), [](const auto& f) { return f.second.hasHostSample; });
      if (flight) {
        begin = flight->beginNs;
        end = flight->endNs;
      } else if (hosted != c.fields.end()) {
        begin = hosted->second.displayNs;
      }
      const auto first =
          std::find_if(c.fields.begin(), c.fields.end(), [&](const auto& f) { return f.second.displayNs >= begin; });
      p.flightFirstField = first != c.fields.end() ? first->first : p.lastField + 1;
      if (begin == std::numeric_limits<std::int64_t>::min()) p.flightFirstField = p.firstField;
      const MissedFields m = missedFields(c.fields, begin, end, stalls, c.fieldCpu, p.missed);
      if (begin != std::numeric_limits<std::int64_t>::min()) p.missedInFlight = std::min(p.missed, m.inFlight);
      p.excusedFields = m.duringStalls;
      if (p.excusedFields.size() > p.missedInFlight) p.excusedFields.resize(p.missedInFlight);
      p.missedInFlightDuringStalls = p.excusedFields.size();
      p.latestEmissionMs = -1e9;
      for (const auto& [k, f] : c.fields) {
        p.latestEmissionMs = std::max(p.latestEmissionMs, static_cast<double>(f.emittedNs - f.displayNs) * 1e-6);
        if (f.emittedNs > f.displayNs) ++p.handedOverLate;
      }
    }
    r.channels.push_back(p);
  }
  if (channels.empty()) return r;
  // With a host, eye positions are compared where every channel flew from a host sample: before
  // its first datagram a channel holds its start pose
  const bool hosted = std::any_of(channels.begin(), channels.end(), [](const ChannelRun& c) {
    return std::any_of(c.fields.begin(), c.fields.end(), [](const auto& f) { return f.second.hasHostSample; });
  });
  std::vector<double> display, emitted, position;
  for (const auto& [k, first] : channels.front().fields) {
    std::vector<const LoggedField*> all;
    for (const ChannelRun& c : channels) {
      const auto it = c.fields.find(k);
      if (it == c.fields.end()) break;
      all.push_back(&it->second);
    }
    if (all.size() != channels.size()) continue;
    ++r.commonFields;
    const auto [dMin, dMax] =
        std::minmax_element(all.begin(), all.end(), [](auto* a, auto* b) { return a->displayNs < b->displayNs; });
    const auto [eMin, eMax] =
        std::minmax_element(all.begin(), all.end(), [](auto* a, auto* b) { return a->emittedNs < b->emittedNs; });
    display.push_back(static_cast<double>((*dMax)->displayNs - (*dMin)->displayNs) * 1e-6);
    emitted.push_back(static_cast<double>((*eMax)->emittedNs - (*eMin)->emittedNs) * 1e-6);
    bool sameHost = first.hostFrame >= 0;
    std::size_t withHostSample = 0;
    double apart = 0;
    for (const LoggedField* f : all) {
      for (const LoggedField* g : all) apart = std::max(apart, std::hypot(f->xM - g->xM, f->yM - g->yM, f->zM - g->zM));
      sameHost = sameHost && f->hostFrame == first.hostFrame;
      withHostSample += f->hasHostSample ? 1 : 0;
    }
    if (sameHost) ++r.sameHostFrame;
    if (withHostSample > 0 && withHostSample < all.size()) ++r.partlyHosted;
    if (!hosted || withHostSample == all.size()) position.push_back(apart);
  }
  r.displayMs = spreadOf(std::move(display));
  r.emittedMs = spreadOf(std::move(emitted));
  r.positionFields = position.size();
  r.positionM = spreadOf(std::move(position));
  return r;
}

std::vector<std::string> lockFailures(const LockReport& r, std::uint64_t allowedMissed) {
  std::vector<std::string> failures;
  for (const auto& c : r.channels) {
    if (c.missedInFlight - c.missedInFlightDuringStalls > allowedMissed)
      failures.push_back(c.name + ": " + std::to_string(c.missedInFlight - c.missedInFlightDuringStalls) +
                         " fields missed while the host flew and the machine ran");
    if (r.flight && (c.fields == 0 || c.lastDisplayNs < r.flight->endNs))
      failures.push_back(c.name + ": its field log ends at field " + std::to_string(c.lastField) +
                         ", before the host's flight ended");
    if (r.flight && c.fields > 0 && c.firstDisplayNs > r.flight->beginNs)
      failures.push_back(c.name + ": its field log begins after the host's flight began");
    if (c.black > 0) failures.push_back(c.name + ": " + std::to_string(c.black) + " fields black");
    if (c.relocks > 0) failures.push_back(c.name + ": moved onto another lock " + std::to_string(c.relocks) + " times");
    if (c.fields + c.missed != c.lastField - c.firstField + 1)
      failures.push_back(c.name + ": " + std::to_string(c.fields) + " fields emitted between field " +
                         std::to_string(c.firstField) + " and " + std::to_string(c.lastField));
  }
  if (r.commonFields == 0) failures.push_back("no field number was made by every channel");
  if (r.displayMs.p99 > 0.5)
    failures.push_back("display times of field k spread " + std::to_string(r.displayMs.p99) +
                       " ms (p99) across channels");
  return failures;
}

nlohmann::json toJson(const LockReport& r) {
  nlohmann::json j;
  j["common_fields"] = r.commonFields;
  j["display_spread_ms"] = toJson(r.displayMs);
  j["emission_spread_ms"] = toJson(r.emittedMs);
  j["position_spread_m"] = toJson(r.positionM);
  j["position_fields"] = r.positionFields;
  j["fields_partly_hosted"] = r.partlyHosted;
  j["same_host_frame"] = r.sameHostFrame;
  j["machine_stalls"] = {{"count", r.machineStalls}, {"longest_ms", r.longestStallMs}};
  if (r.flight) j["flight_monotonic_ns"] = {r.flight->beginNs, r.flight->endNs};
  for (const auto& c : r.channels) {
    j["channels"].push_back({{"name", c.name},
                             {"fields", c.fields},
                             {"missed", c.missed},
                             {"field_thread_cpu", c.fieldCpu},
                             {"flight_first_field", c.flightFirstField},
                             {"missed_in_flight", c.missedInFlight},
                             {"missed_in_flight_during_machine_stalls", c.missedInFlightDuringStalls},
                             {"fields_missed_during_machine_stalls", c.excusedFields},
                             {"black", c.black},
                             {"first_field", c.firstField},
                             {"last_field", c.lastField},
                             {"relocks", c.relocks},
                             {"latest_emission_from_display_ms", c.latestEmissionMs},
                             {"handed_over_late", c.handedOverLate}});
  }
  return j;
}

std::string describe(const LockReport& r) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(3);
  for (const auto& c : r.channels) {
    s << c.name << ": fields " << c.firstField << "–" << c.lastField << ", " << c.fields << " emitted, " << c.missed
      << " missed (" << c.missedInFlight << " from field " << c.flightFirstField << ", when the host flew, "
      << c.missedInFlightDuringStalls << " of them while the machine stalled), " << c.black << " black, " << c.relocks
      << " relocks; " << c.handedOverLate << " handed over after their display time, the latest " << c.latestEmissionMs
      << " ms after\n";
    if (!c.excusedFields.empty()) {
      s << "  " << c.name << ": fields missed while its field thread's CPU stalled:";
      for (const std::uint64_t k : c.excusedFields) s << ' ' << k;
      s << '\n';
    }
  }
  s << "fields every channel made: " << r.commonFields << "\n"
    << "display time of field k across channels: spread p50 " << r.displayMs.p50 << " ms, p99 " << r.displayMs.p99
    << " ms, max " << r.displayMs.max << " ms\n"
    << "emission of field k across channels: spread p50 " << r.emittedMs.p50 << " ms, p99 " << r.emittedMs.p99
    << " ms, max " << r.emittedMs.max << " ms\n"
    << "eye positions at one field (" << r.positionFields
    << " fields, every channel flying from a host sample): apart p50 " << r.positionM.p50 << " m, p99 "
    << r.positionM.p99 << " m, max " << r.positionM.max << " m; " << r.sameHostFrame
    << " fields made from the same host sample in every channel, " << r.partlyHosted
    << " where some channels had the host's first sample and others not yet\n"
    << "machine stalls (fieldcast-stall-probe): " << r.machineStalls << ", the longest " << r.longestStallMs << " ms\n";
  return s.str();
}

}  // namespace fieldcast::tools
