#include <service/ServiceMetrics.h>
#include "ThreadScheduling.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
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

TEST(ThreadScheduling, ReportsWhatWasGrantedWithoutThrowing) {
  std::string report;
  std::thread([&] { report = applyScheduling("fc-test", ThreadScheduling{true, 10, 3, -1}); }).join();
  // Either granted or refused with the reason: never silent.
  EXPECT_TRUE(report.find("SCHED_FIFO priority 10") != std::string::npos ||
              report.find("SCHED_FIFO refused") != std::string::npos)
      << report;
  std::thread([&] { report = applyScheduling("fc-test", ThreadScheduling{false, 0, 5, 0}); }).join();
  EXPECT_NE(report.find("nice 5"), std::string::npos) << report;
  EXPECT_NE(report.find("CPU 0"), std::string::npos) << report;
}

}  // namespace
}  // namespace fieldcast::app
