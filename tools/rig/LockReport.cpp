// The rig's lock figures from the channels' field logs and summaries.
#include "LockReport.h"

#include <algorithm>
#include <cmath>
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

nlohmann::json toJson(const Spread& s) { return {{"p50", s.p50}, {"p99", s.p99}, {"max", s.max}}; }

}  // namespace

LockReport lockReport(const std::vector<ChannelRun>& channels) {
  LockReport r;
  for (const ChannelRun& c : channels) {
    LockReport::PerChannel p;
    p.name = c.name;
    p.fields = c.summary.value("fields_emitted", std::uint64_t{0});
    p.missed = c.summary.value("fields_missed", std::uint64_t{0});
    p.black = c.summary.value("fields_black", std::uint64_t{0});
    if (c.summary.contains("lock")) p.relocks = c.summary["lock"].value("relocks", std::uint64_t{0});
    if (!c.fields.empty()) {
      // The first field planned (a missed first field is not in the log)
      p.firstField = c.summary.contains("lock") ? c.summary["lock"].value("first_field", c.fields.begin()->first)
                                                : c.fields.begin()->first;
      p.lastField = c.fields.rbegin()->first;
      p.latestEmissionMs = -1e9;
      for (const auto& [k, f] : c.fields) {
        p.latestEmissionMs = std::max(p.latestEmissionMs, static_cast<double>(f.emittedNs - f.displayNs) * 1e-6);
        if (f.emittedNs > f.displayNs) ++p.handedOverLate;
      }
    }
    r.channels.push_back(p);
  }
  if (channels.empty()) return r;
  std::vector<double> display, emitted;
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
    for (const LoggedField* f : all) {
      r.positionSpreadMaxM =
          std::max(r.positionSpreadMaxM, std::hypot(f->xM - first.xM, f->yM - first.yM, f->zM - first.zM));
      sameHost = sameHost && f->hostFrame == first.hostFrame;
    }
    if (sameHost) ++r.sameHostFrame;
  }
  r.displayMs = spreadOf(std::move(display));
  r.emittedMs = spreadOf(std::move(emitted));
  return r;
}

std::vector<std::string> lockFailures(const LockReport& r, std::uint64_t allowedMissed) {
  std::vector<std::string> failures;
  for (const auto& c : r.channels) {
    if (c.missed > allowedMissed) failures.push_back(c.name + ": " + std::to_string(c.missed) + " fields missed");
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
  j["position_spread_max_m"] = r.positionSpreadMaxM;
  j["same_host_frame"] = r.sameHostFrame;
  for (const auto& c : r.channels) {
    j["channels"].push_back({{"name", c.name},
                             {"fields", c.fields},
                             {"missed", c.missed},
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
      << " missed, " << c.black << " black, " << c.relocks << " relocks; " << c.handedOverLate
      << " handed over after their display time, the latest " << c.latestEmissionMs << " ms after\n";
  }
  s << "fields every channel made: " << r.commonFields << "\n"
    << "display time of field k across channels: spread p50 " << r.displayMs.p50 << " ms, p99 " << r.displayMs.p99
    << " ms, max " << r.displayMs.max << " ms\n"
    << "emission of field k across channels: spread p50 " << r.emittedMs.p50 << " ms, p99 " << r.emittedMs.p99
    << " ms, max " << r.emittedMs.max << " ms\n"
    << "eye positions at one field: at most " << r.positionSpreadMaxM << " m apart; " << r.sameHostFrame
    << " fields made from the same host sample in every channel\n";
  return s.str();
}

}  // namespace fieldcast::tools
