#include <ig_core/RenderConfig.h>
#include <service/ServiceMetrics.h>
#include "ThreadScheduling.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <pthread.h>
#include <sched.h>

#include <chrono>
#include <cstdio>
#include <thread>

namespace fieldcast::app {
namespace {

using std::chrono::milliseconds;

TEST(ServiceMetrics, IntervalLineReportsTheIntervalOnlyAndTotalsKeepEverything) {
  ServiceMetrics metrics;
  const TimePoint t0 = MonotonicClock::now();
  metrics.counters.fieldsEmitted += 60;
  metrics.counters.framesRendered += 15;
  metrics.record(Measure::WarpTime, milliseconds(2));
  const std::string first = metrics.intervalLine(t0 + std::chrono::seconds(1));
  EXPECT_NE(first.find("fields 60 missed 0"), std::string::npos) << first;
  EXPECT_NE(first.find("warp 2.0"), std::string::npos) << first;

  metrics.counters.fieldsEmitted += 59;
  metrics.counters.fieldsMissed += 1;
  metrics.record(Measure::WarpTime, milliseconds(4));
  const std::string second = metrics.intervalLine(t0 + std::chrono::seconds(2));
  EXPECT_NE(second.find("fields 59 missed 1"), std::string::npos) << second;
  EXPECT_NE(second.find("render 0.0 Hz"), std::string::npos) << second;

  const ServiceFigures f = metrics.figures(t0 + std::chrono::seconds(2));
  EXPECT_EQ(f.fieldsEmitted, 119u);
  EXPECT_EQ(f.fieldsMissed, 1u);
  EXPECT_EQ(f.warp.count, 2u);
  EXPECT_NEAR(f.warp.maxS, 0.004, 1e-4);
}

TEST(ServiceMetrics, TileMissesArePerIntervalAfterTheStartUp) {
  ServiceMetrics metrics;
  StartupFigures startup;
  startup.tileMisses = 5000;  // the first frames' misses, before the prefetch landed
  metrics.setStartup(startup);
  EXPECT_EQ(metrics.tileMissesSince(5040), 40u);
  EXPECT_EQ(metrics.tileMissesSince(5040), 0u);  // a quiet interval says 0, not the total
  EXPECT_EQ(metrics.tileMissesSince(5047), 7u);
  const ServiceFigures f = metrics.figures(MonotonicClock::now());
  EXPECT_EQ(f.startup.tileMisses, 5000u);
  EXPECT_EQ(f.tileMissesRun, 47u);
  const nlohmann::json j = toJson(f);
  EXPECT_EQ(j.at("startup").at("tile_misses").get<int>(), 5000);
  EXPECT_EQ(j.at("tile_misses_run").get<int>(), 47);
}

TEST(ServiceMetrics, WarpFallbacksAreCountedByReason) {
  ServiceMetrics metrics;
  metrics.counters.warpFallbacks += 6;
  metrics.counters.warpFallbacksByReason[0] += 1;
  metrics.counters.warpFallbacksByReason[1] += 3;
  metrics.counters.warpFallbacksByReason[2] += 2;
  const ServiceFigures f = metrics.figures(MonotonicClock::now());
  const nlohmann::json j = toJson(f).at("warp_fallbacks_by_reason");
  EXPECT_EQ(j.at("few_points").get<int>(), 1);
  EXPECT_EQ(j.at("all_sky").get<int>(), 3);
  EXPECT_EQ(j.at("degenerate").get<int>(), 2);
  EXPECT_EQ(j.at("no_range_image").get<int>(), 0);
  EXPECT_NE(describe(f).find("6 warp fallbacks (few points 1, all sky 3, degenerate 2, no range image 0)"),
            std::string::npos)
      << describe(f);
}

TEST(Visibility, DefaultFollowsTheDatabaseExtent) {
  EXPECT_DOUBLE_EQ(core::defaultVisibilityM(16384.0), 12288.0);  // the built-in terrain: about the old 12 km
  EXPECT_DOUBLE_EQ(core::defaultVisibilityM(70000.0), 52500.0);  // a 70 km database is not a wall of haze
  EXPECT_DOUBLE_EQ(core::defaultVisibilityM(1024.0), 3000.0);    // the floor for a small one
}

TEST(ServiceMetrics, StickLatencyAppearsOnlyWhenMeasured) {
  ServiceMetrics metrics;
  EXPECT_EQ(metrics.intervalLine(MonotonicClock::now()).find("stick"), std::string::npos);
  metrics.record(Measure::StickLatency, milliseconds(30));
  EXPECT_NE(metrics.intervalLine(MonotonicClock::now()).find("stick→field 30"), std::string::npos);
}

TEST(ServiceMetrics, ReportsTheQualityKnobTheFramesWereRenderedWith) {
  ServiceMetrics metrics;
  const TimePoint t0 = MonotonicClock::now();
  EXPECT_EQ(metrics.intervalLine(t0).find("quality"), std::string::npos);  // no frame yet
  // Interval 1: three frames at the default knob, the grazing rule on for one.
  for (const bool grazing : {false, true, false}) metrics.recordFrame(1.0, grazing);
  const std::string first = metrics.intervalLine(t0 + std::chrono::seconds(1));
  EXPECT_NE(first.find("quality 1.00 grazing 33%"), std::string::npos) << first;
  // Interval 2: the controller coarsened, with the grazing rule on for three frames in four.
  for (const double q : {2.0, 2.5, 3.0, 3.5}) metrics.recordFrame(q, q > 2.0);
  const std::string second = metrics.intervalLine(t0 + std::chrono::seconds(2));
  EXPECT_NE(second.find("quality 2.75 grazing 75%"), std::string::npos) << second;
  // Interval 3: the rule off again.
  metrics.recordFrame(1.5, false);
  const std::string third = metrics.intervalLine(t0 + std::chrono::seconds(3));
  EXPECT_NE(third.find("quality 1.50"), std::string::npos) << third;
  EXPECT_EQ(third.find("grazing"), std::string::npos) << third;

  const ServiceFigures f = metrics.figures(t0 + std::chrono::seconds(3));
  EXPECT_EQ(f.framesRendered, 8u);
  EXPECT_NEAR(f.meanQuality, (3 * 1.0 + 2.0 + 2.5 + 3.0 + 3.5 + 1.5) / 8, 1e-9);
  EXPECT_EQ(f.framesGrazing, 4u);
  const nlohmann::json j = toJson(f);
  EXPECT_NEAR(j.at("mean_quality").get<double>(), f.meanQuality, 1e-12);
  EXPECT_EQ(j.at("frames_grazing").get<int>(), 4);
  EXPECT_NE(describe(f).find("quality knob mean 1.94, grazing-angle rule on for 4 of 8 frames"), std::string::npos)
      << describe(f);
}

TEST(ServiceMetrics, JsonSummaryHasTheFiguresScriptsRead) {
  ServiceMetrics metrics;
  metrics.counters.fieldsEmitted += 10;
  metrics.record(Measure::FieldJitter, std::chrono::microseconds(50));
  const nlohmann::json j = toJson(metrics.figures(MonotonicClock::now()));
  EXPECT_EQ(j.at("fields_emitted").get<int>(), 10);
  EXPECT_EQ(j.at("fields_missed").get<int>(), 0);
  EXPECT_EQ(j.at("field_jitter").at("count").get<int>(), 1);
  EXPECT_NEAR(j.at("field_jitter").at("max_ms").get<double>(), 0.05, 0.002);
}

TEST(ThreadScheduling, ReportsWhatWasGrantedAndTheThreadRunsThatWay) {
  // Whether this process may use SCHED_FIFO at all, found independently of applyScheduling.
  bool fifoAllowed = false;
  std::thread([&] {
    sched_param param{};
    param.sched_priority = 10;
    fifoAllowed = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
  }).join();
  std::string report;
  int policy = -1;
  sched_param param{};
  std::thread([&] {
    report = applyScheduling("fc-test", ThreadScheduling{true, 10, 3, -1});
    pthread_getschedparam(pthread_self(), &policy, &param);  // what the thread really runs with
  }).join();
  if (fifoAllowed) {
    EXPECT_EQ(policy, SCHED_FIFO) << report;
    EXPECT_EQ(param.sched_priority, 10) << report;
    EXPECT_NE(report.find("SCHED_FIFO priority 10"), std::string::npos) << report;
  } else {
    EXPECT_EQ(policy, SCHED_OTHER) << report;
    EXPECT_NE(report.find("SCHED_FIFO refused: "), std::string::npos) << report;
    EXPECT_NE(report.find("running as SCHED_OTHER"), std::string::npos) << report;
  }
  std::printf("SCHED_FIFO %s here: %s\n", fifoAllowed ? "granted" : "refused", report.c_str());
  std::thread([&] { report = applyScheduling("fc-test", ThreadScheduling{false, 0, 5, 0}); }).join();
  EXPECT_NE(report.find("nice 5"), std::string::npos) << report;
  EXPECT_NE(report.find("CPU 0"), std::string::npos) << report;
}

}  // namespace
}  // namespace fieldcast::app
