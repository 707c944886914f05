#include <service/ServiceMetrics.h>

#include "FieldLog.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>

namespace fieldcast::app {
namespace {

std::string ms(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", seconds * 1e3);
  return text;
}

nlohmann::json toJson(const DurationSummary& s) {
  return {{"count", s.count},
          {"p50_ms", s.p50S * 1e3},
          {"p99_ms", s.p99S * 1e3},
          {"max_ms", s.maxS * 1e3},
          {"mean_ms", s.meanS * 1e3}};
}

double mean(std::uint64_t sum, std::uint64_t count) {
  return count > 0 ? static_cast<double>(sum) / static_cast<double>(count) : 0.0;
}

}  // namespace

ServiceMetrics::ServiceMetrics() : mStart(MonotonicClock::now()), mLast(mStart) {}

ServiceMetrics::~ServiceMetrics() = default;

void ServiceMetrics::openFieldLog(const std::filesystem::path& path) { mFieldLog = std::make_unique<FieldLog>(path); }

void ServiceMetrics::closeFieldLog() {
  if (mFieldLog) mFieldLog->stop();
}

std::string ServiceMetrics::intervalLine(TimePoint now) {
  const double seconds = std::max(1e-9, toSeconds(now - mLast));
  // The knobs first (see recordFrame): every frame they count is then in `frames`.
  const auto qualityMilli = counters.qualityMilliSum.load(std::memory_order_acquire);
  const auto grazing = counters.framesGrazing.load(std::memory_order_acquire);
  const auto frames = counters.framesRendered.load(std::memory_order_relaxed);
  const auto fields = counters.fieldsEmitted.load(std::memory_order_relaxed);
  const auto missed = counters.fieldsMissed.load(std::memory_order_relaxed);
  const auto margin = counters.marginViolations.load(std::memory_order_relaxed);

  DurationSummary s[static_cast<int>(Measure::kCount)];
  for (int m = 0; m < static_cast<int>(Measure::kCount); ++m) {
    mInterval[m].drainInto(mScratch);
    s[m] = mScratch.summary();
    mTotal[m].merge(mScratch);
  }
  mLastRenderHz = static_cast<double>(frames - mLastFrames) / seconds;
  char line[512];
  std::snprintf(
      line, sizeof line, "render %.1f Hz | fields %llu missed %llu | margin px %llu | warp %s/%s ms",
      static_cast<double>(frames - mLastFrames) / seconds, static_cast<unsigned long long>(fields - mLastFields),
      static_cast<unsigned long long>(missed - mLastMissed), static_cast<unsigned long long>(margin - mLastMargin),
      ms(s[static_cast<int>(Measure::WarpTime)].p50S).c_str(), ms(s[static_cast<int>(Measure::WarpTime)].p99S).c_str());
  std::string result = line;
  if (const auto rendered = frames - mLastFrames; rendered > 0) {
    // What the frame-time controller chose: the mean knob, and how often the grazing rule was on.
    std::snprintf(line, sizeof line, " | quality %.2f", mean(qualityMilli - mLastQualityMilli, rendered) / 1000.0);
    result += line;
    if (grazing > mLastGrazing) {
      std::snprintf(line, sizeof line, " grazing %.0f%%",
                    100.0 * std::min(1.0, mean(grazing - mLastGrazing, rendered)));
      result += line;
    }
  }
  const DurationSummary& age = s[static_cast<int>(Measure::FrameAge)];
  if (age.count > 0) result += " | frame age " + ms(age.p50S) + "/" + ms(age.p99S) + " ms";
  const DurationSummary& stick = s[static_cast<int>(Measure::StickLatency)];
  if (stick.count > 0) result += " | stick→field " + ms(stick.p50S) + "/" + ms(stick.p99S) + " ms";
  const DurationSummary& host = s[static_cast<int>(Measure::HostToEmission)];
  if (host.count > 0) result += " | host→field " + ms(host.p50S) + "/" + ms(host.p99S) + " ms";
  result += " (p50/p99)";
  mLast = now;
  mLastFrames = frames;
  mLastFields = fields;
  mLastMissed = missed;
  mLastMargin = margin;
  mLastQualityMilli = qualityMilli;
  mLastGrazing = grazing;
  return result;
}

ServiceFigures ServiceMetrics::figures(TimePoint now) {
  for (int m = 0; m < static_cast<int>(Measure::kCount); ++m) {
    mInterval[m].drainInto(mScratch);
    mTotal[m].merge(mScratch);
  }
  ServiceFigures f;
  f.durationS = toSeconds(now - mStart);
  f.framesRendered = counters.framesRendered.load();
  f.fieldsEmitted = counters.fieldsEmitted.load();
  f.fieldsBlack = counters.fieldsBlack.load();
  f.fieldsHeld = counters.fieldsHeld.load();
  f.fieldsMissed = counters.fieldsMissed.load();
  f.marginViolations = counters.marginViolations.load();
  f.warpFallbacks = counters.warpFallbacks.load();
  f.fallbacksFewPoints = counters.warpFallbacksByReason[0].load();
  f.fallbacksAllSky = counters.warpFallbacksByReason[1].load();
  f.fallbacksDegenerate = counters.warpFallbacksByReason[2].load();
  f.fallbacksNoRange = counters.warpFallbacksByReason[3].load();
  f.fieldsMissedFirstSecond = counters.fieldsMissedFirstSecond.load();
  f.fieldsLate = counters.fieldsLate.load();
  f.startup = mStartup;
  f.tileMissesRun = mLastTileMisses - mStartup.tileMisses;
  f.visibilityM = mVisibilityM;
  f.meanQuality = mean(counters.qualityMilliSum.load(), f.framesRendered) / 1000.0;
  f.framesGrazing = counters.framesGrazing.load();
  f.render = mTotal[static_cast<int>(Measure::RenderTime)].summary();
  f.warp = mTotal[static_cast<int>(Measure::WarpTime)].summary();
  f.frameAge = mTotal[static_cast<int>(Measure::FrameAge)].summary();
  f.jitter = mTotal[static_cast<int>(Measure::FieldJitter)].summary();
  f.stickLatency = mTotal[static_cast<int>(Measure::StickLatency)].summary();
  f.hostToEmission = mTotal[static_cast<int>(Measure::HostToEmission)].summary();
  f.hostToDisplay = mTotal[static_cast<int>(Measure::HostToDisplay)].summary();
  if (mFieldLog) {
    f.fieldLogPath = mFieldLog->path().string();
    f.fieldLogRecords = mFieldLog->written();
    f.fieldLogDropped = mFieldLog->dropped();
  }
  return f;
}

nlohmann::json toJson(const ServiceFigures& f) {
  nlohmann::json j = {{"duration_s", f.durationS},
                      {"frames_rendered", f.framesRendered},
                      {"render_hz", f.durationS > 0 ? static_cast<double>(f.framesRendered) / f.durationS : 0.0},
                      {"fields_emitted", f.fieldsEmitted},
                      {"fields_black", f.fieldsBlack},
                      {"fields_held", f.fieldsHeld},
                      {"fields_missed", f.fieldsMissed},
                      {"fields_late", f.fieldsLate},
                      {"margin_violation_px", f.marginViolations},
                      {"warp_fallbacks", f.warpFallbacks},
                      {"warp_fallbacks_by_reason",
                       {{"few_points", f.fallbacksFewPoints},
                        {"all_sky", f.fallbacksAllSky},
                        {"degenerate", f.fallbacksDegenerate},
                        {"no_range_image", f.fallbacksNoRange}}},
                      {"fields_missed_first_second", f.fieldsMissedFirstSecond},
                      {"startup",
                       {{"to_first_field_s", f.startup.toFirstFieldS},
                        {"warm_up_warp_ms", f.startup.warmUpWarpMs},
                        {"warm_up_frame", f.startup.warmUpFrame},
                        {"memory_locked", f.startup.memoryLocked},
                        {"tile_misses", f.startup.tileMisses}}},
                      {"tile_misses_run", f.tileMissesRun},
                      {"visibility_m", f.visibilityM},
                      {"mean_quality", f.meanQuality},
                      {"frames_grazing", f.framesGrazing},
                      {"render_time", toJson(f.render)},
                      {"warp_time", toJson(f.warp)},
                      {"frame_age", toJson(f.frameAge)},
                      {"field_jitter", toJson(f.jitter)},
                      {"stick_latency", toJson(f.stickLatency)}};
  if (f.hostToEmission.count > 0) {
    j["host_to_field_emission"] = toJson(f.hostToEmission);
    j["host_to_field_display"] = toJson(f.hostToDisplay);
  }
  if (!f.fieldLogPath.empty()) {
    j["field_log"] = {{"path", f.fieldLogPath}, {"records", f.fieldLogRecords}, {"dropped", f.fieldLogDropped}};
  }
  return j;
}

std::string describe(const ServiceFigures& f) {
  char text[1024];
  std::snprintf(
      text, sizeof text,
      "ran %.1f s: %llu frames (%.1f Hz), %llu fields emitted (%llu black before the first frame), "
      "%llu missed (%llu in the first second), %llu late, %llu margin-violation px, %llu warp fallbacks "
      "(few points %llu, all sky %llu, degenerate %llu, no range image %llu)\n"
      "  render ms p50 %s p99 %s | warp ms p50 %s p99 %s max %s | frame age ms p50 %s p99 %s | "
      "field jitter ms p50 %s p99 %s max %s",
      f.durationS, static_cast<unsigned long long>(f.framesRendered),
      f.durationS > 0 ? static_cast<double>(f.framesRendered) / f.durationS : 0.0,
      static_cast<unsigned long long>(f.fieldsEmitted), static_cast<unsigned long long>(f.fieldsBlack),
      static_cast<unsigned long long>(f.fieldsMissed), static_cast<unsigned long long>(f.fieldsMissedFirstSecond),
      static_cast<unsigned long long>(f.fieldsLate), static_cast<unsigned long long>(f.marginViolations),
      static_cast<unsigned long long>(f.warpFallbacks), static_cast<unsigned long long>(f.fallbacksFewPoints),
      static_cast<unsigned long long>(f.fallbacksAllSky), static_cast<unsigned long long>(f.fallbacksDegenerate),
      static_cast<unsigned long long>(f.fallbacksNoRange), ms(f.render.p50S).c_str(), ms(f.render.p99S).c_str(),
      ms(f.warp.p50S).c_str(), ms(f.warp.p99S).c_str(), ms(f.warp.maxS).c_str(), ms(f.frameAge.p50S).c_str(),
      ms(f.frameAge.p99S).c_str(), ms(f.jitter.p50S).c_str(), ms(f.jitter.p99S).c_str(), ms(f.jitter.maxS).c_str());
  std::string result = text;
  std::snprintf(text, sizeof text,
                "\n  start-up %.2f s to the first field (warm-up warp %.2f ms, memory %s), %llu tile misses before it, "
                "%llu after",
                f.startup.toFirstFieldS, f.startup.warmUpWarpMs, f.startup.memoryLocked ? "locked" : "not locked",
                static_cast<unsigned long long>(f.startup.tileMisses),
                static_cast<unsigned long long>(f.tileMissesRun));
  result += text;
  if (f.framesRendered > 0) {
    std::snprintf(text, sizeof text, "\n  quality knob mean %.2f, grazing-angle rule on for %llu of %llu frames",
                  f.meanQuality, static_cast<unsigned long long>(f.framesGrazing),
                  static_cast<unsigned long long>(f.framesRendered));
    result += text;
  }
  if (f.stickLatency.count > 0) {
    result += "\n  stick→field ms p50 " + ms(f.stickLatency.p50S) + " p99 " + ms(f.stickLatency.p99S);
  }
  if (f.hostToEmission.count > 0) {
    result += "\n  host datagram→first field using it ms: emission p50 " + ms(f.hostToEmission.p50S) + " p99 " +
              ms(f.hostToEmission.p99S) + ", display p50 " + ms(f.hostToDisplay.p50S) + " p99 " +
              ms(f.hostToDisplay.p99S);
  }
  if (!f.fieldLogPath.empty()) {
    std::snprintf(text, sizeof text, "\n  field log %s: %llu records, %llu dropped", f.fieldLogPath.c_str(),
                  static_cast<unsigned long long>(f.fieldLogRecords),
                  static_cast<unsigned long long>(f.fieldLogDropped));
    result += text;
  }
  return result;
}

}  // namespace fieldcast::app
