// Discrete inputs and the external sync, through the fake line seam; the libgpiod back end's
// error path against this machine.
#include <io_bridge/ExternalSync.h>
#include <io_bridge/GpioInput.h>

#include "FakeGpioLine.h"

#include <gtest/gtest.h>

#include <thread>

namespace fieldcast::io {
namespace {

using namespace std::chrono_literals;
using testing::FakeGpioLine;

constexpr std::int64_t kMs = 1'000'000;
const RationalRate kNtsc{60000, 1001};

TEST(GpioInputs, DebouncedPressesWithKernelTimes) {
  auto wire = std::make_shared<FakeGpioLine::Wire>();
  GpioInputs inputs(5ms, kNtsc);
  inputs.addDiscrete(Discrete::Freeze, std::make_unique<FakeGpioLine>(wire));
  wire->edge(10 * kMs, GpioEdgeKind::Rising);
  wire->edge(11 * kMs, GpioEdgeKind::Falling);  // contact bounce
  wire->edge(12 * kMs, GpioEdgeKind::Rising);   // contact bounce
  ASSERT_TRUE(inputs.pump(0ms));
  DiscreteSnapshot s = inputs.discretes();
  EXPECT_TRUE(s.isOn(Discrete::Freeze));
  EXPECT_EQ(s.pressCount(Discrete::Freeze), 1u);
  EXPECT_EQ(s.lastEdgeNs[0], 10 * kMs);
  EXPECT_EQ(s.bounces, 2u);
  wire->edge(100 * kMs, GpioEdgeKind::Falling);
  wire->edge(101 * kMs, GpioEdgeKind::Rising);  // bounce of the release
  wire->edge(300 * kMs, GpioEdgeKind::Rising);
  inputs.pump(0ms);
  s = inputs.discretes();
  EXPECT_TRUE(s.isOn(Discrete::Freeze));
  EXPECT_EQ(s.pressCount(Discrete::Freeze), 2u);
  EXPECT_EQ(s.pressCount(Discrete::Reset), 0u);
  EXPECT_EQ(s.bounces, 3u);
}

TEST(GpioInputs, InitialLevelAndLostLine) {
  auto wire = std::make_shared<FakeGpioLine::Wire>();
  wire->level = true;
  GpioInputs inputs(5ms, kNtsc);
  inputs.addDiscrete(Discrete::Reset, std::make_unique<FakeGpioLine>(wire));
  EXPECT_TRUE(inputs.discretes().isOn(Discrete::Reset));
  wire->unplug();
  EXPECT_TRUE(inputs.pump(10ms));   // reads the loss
  EXPECT_FALSE(inputs.pump(10ms));  // no line left
}

TEST(GpioInputs, ThreadPublishesToAnotherThread) {
  auto trigger = std::make_shared<FakeGpioLine::Wire>();
  auto sync = std::make_shared<FakeGpioLine::Wire>();
  GpioInputs inputs(1ms, kNtsc);
  inputs.addDiscrete(Discrete::Trigger, std::make_unique<FakeGpioLine>(trigger));
  inputs.addSync(std::make_unique<FakeGpioLine>(sync));
  inputs.start();
  trigger->edge(5 * kMs, GpioEdgeKind::Rising);
  for (int k = 0; k < 20; ++k) sync->edge(1'000 * kMs + k * 16'683'333, GpioEdgeKind::Rising);
  for (int i = 0; i < 2000 && (inputs.discretes().pressCount(Discrete::Trigger) == 0 || inputs.sync().pulses < 20);
       ++i) {
    std::this_thread::sleep_for(1ms);
  }
  inputs.stop();
  EXPECT_EQ(inputs.discretes().pressCount(Discrete::Trigger), 1u);
  EXPECT_EQ(inputs.sync().pulses, 20u);
  EXPECT_TRUE(inputs.sync().locked);
}

// Deterministic jitter in [-amp, amp].
std::int64_t jitter(int k, std::int64_t amp) { return ((k * 7919) % 201 - 100) * amp / 100; }

TEST(ExternalSync, FitsPeriodAndPhaseThroughJitter) {
  ExternalSyncEstimator est(kNtsc);
  const double period = 1e9 * 1001.0 / 60000.0;  // 16 683 333.3 ns
  const std::int64_t t0 = 5'000'000'000;
  for (int k = 0; k < 200; ++k) {
    est.onPulse(TimePoint{Nanoseconds{t0 + static_cast<std::int64_t>(k * period) + jitter(k, 20'000)}});
  }
  const SyncEstimate s = est.estimate();
  EXPECT_TRUE(s.locked);
  EXPECT_NEAR(s.periodNs, period, 100.0);  // ±20 µs jitter, 64-pulse window
  EXPECT_NEAR(static_cast<double>(s.lastPulse.time_since_epoch().count()), t0 + 199 * period, 10'000.0);
  EXPECT_LT(s.jitterRmsNs, 20'000.0);
  EXPECT_GT(s.jitterRmsNs, 1'000.0);
  EXPECT_EQ(s.pulses, 200u);
}

TEST(ExternalSync, MissingPulsesGlitchesAndOutages) {
  ExternalSyncEstimator est(RationalRate{50, 1});  // 20 ms
  std::int64_t t = 1'000'000'000;
  for (int k = 0; k < 10; ++k, t += 20 * kMs) est.onPulse(TimePoint{Nanoseconds{t}});
  EXPECT_TRUE(est.estimate().locked);
  t += 20 * kMs;  // one pulse missing
  est.onPulse(TimePoint{Nanoseconds{t}});
  EXPECT_EQ(est.estimate().missed, 1u);
  EXPECT_NEAR(est.estimate().periodNs, 20e6, 1.0);
  est.onPulse(TimePoint{Nanoseconds{t + 3 * kMs}});  // a glitch
  EXPECT_EQ(est.estimate().glitches, 1u);
  EXPECT_EQ(est.estimate().predict(2), TimePoint{Nanoseconds{t + 40 * kMs}});
  est.onPulse(TimePoint{Nanoseconds{t + 2000 * kMs}});  // a long outage: start over
  EXPECT_FALSE(est.estimate().locked);
}

TEST(GpioLineSpec, ParsesChipOffsetAndFlags) {
  const GpioLineConfig c = parseGpioLineSpec("gpiochip1:17:active_low:pull_up");
  EXPECT_EQ(c.chip, "gpiochip1");
  EXPECT_EQ(c.offset, 17u);
  EXPECT_TRUE(c.activeLow);
  EXPECT_EQ(c.bias, GpioBias::PullUp);
  EXPECT_EQ(parseGpioLineSpec("/dev/gpiochip0:3").bias, GpioBias::AsIs);
  auto errorOf = [](const char* s) {
    try {
      (void)parseGpioLineSpec(s);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(errorOf("gpiochip0"),
            "GPIO line \"gpiochip0\": expected chip:offset[:active_low][:pull_up|:pull_down|:bias_off]");
  EXPECT_EQ(errorOf("gpiochip0:x"), "GPIO line \"gpiochip0:x\": line offset \"x\" is not a number");
  EXPECT_EQ(errorOf("gpiochip0:1:pullup"),
            "GPIO line \"gpiochip0:1:pullup\": unknown flag \"pullup\" (expected active_low, pull_up, pull_down or "
            "bias_off)");
  EXPECT_EQ(errorOf("gpiochip0:1:pull_up:pull_down"),
            "GPIO line \"gpiochip0:1:pull_up:pull_down\": more than one bias flag");
}

TEST(GpiodBackend, RefusesAnAbsentChipWithTheReason) {
  try {
    (void)openGpiodEdgeLine(GpioLineConfig{"fieldcast-no-such-chip", 3, false, GpioBias::AsIs, "fieldcast-test"});
    ADD_FAILURE() << "opened a chip that does not exist";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("GPIO chip \"fieldcast-no-such-chip\""), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldcast::io
