#include <io_bridge/GpioPulseSink.h>

#include "TestFields.h"

#include <gtest/gtest.h>

namespace fieldcast::io {
namespace {

using testing::makeField;
using testing::testFormat;

// Records every edge with the (virtual) time it happened.
struct Edge {
  TimePoint t;
  bool high;
};
class FakeLine final : public PulseLine {
 public:
  FakeLine(std::shared_ptr<Clock> clock, std::vector<Edge>* edges) : mClock(std::move(clock)), mEdges(edges) {}
  void set(bool high) noexcept override { mEdges->push_back({mClock->now(), high}); }
  std::string describe() const override { return "fake"; }

 private:
  std::shared_ptr<Clock> mClock;
  std::vector<Edge>* mEdges;
};

TEST(GpioPulseSink, HighAtEachDisplayTimeForTheWidth) {
  const TimePoint t0{std::chrono::seconds(50)};
  auto clock = std::make_shared<VirtualClock>(t0 - std::chrono::milliseconds(5));
  std::vector<Edge> edges;
  GpioPulseSink sink(std::make_unique<FakeLine>(clock, &edges), {std::chrono::microseconds(300)}, clock);
  const StreamFormat f = testFormat(64, 16);
  sink.open(f);
  edges.clear();
  for (std::uint64_t k = 0; k < 4; ++k) sink.consume(makeField(f, k, t0));
  ASSERT_EQ(edges.size(), 8u);
  for (std::size_t k = 0; k < 4; ++k) {
    const TimePoint tk = t0 + f.fieldRate.tickOffset(static_cast<std::int64_t>(k));
    EXPECT_TRUE(edges[2 * k].high);
    EXPECT_EQ(edges[2 * k].t, tk);
    EXPECT_FALSE(edges[2 * k + 1].high);
    EXPECT_EQ(edges[2 * k + 1].t, tk + std::chrono::microseconds(300));
  }
  EXPECT_EQ(sink.pulses(), 4u);
}

TEST(GpioPulseSink, ALateFieldGetsNoPulse) {
  const TimePoint t0{std::chrono::seconds(50)};
  auto clock = std::make_shared<VirtualClock>(t0);
  std::vector<Edge> edges;
  GpioPulseSink sink(std::make_unique<FakeLine>(clock, &edges), {}, clock);
  const StreamFormat f = testFormat(64, 16);
  sink.open(f);
  edges.clear();
  clock->advance(std::chrono::milliseconds(40));  // fields 0–2 are already past
  for (std::uint64_t k = 0; k < 4; ++k) sink.consume(makeField(f, k, t0));
  EXPECT_EQ(sink.latePulses(), 3u);  // fields at 0, 16.7 and 33.4 ms; 50.1 ms is still ahead
  EXPECT_EQ(sink.pulses() + sink.latePulses(), 4u);
  for (const Edge& e : edges) EXPECT_GE(e.t, t0 + std::chrono::milliseconds(40));
}

TEST(GpioPulseSink, WidthMustBeShorterThanAField) {
  auto clock = std::make_shared<VirtualClock>();
  std::vector<Edge> edges;
  GpioPulseSink sink(std::make_unique<FakeLine>(clock, &edges), {std::chrono::milliseconds(20)}, clock);
  EXPECT_THROW(sink.open(testFormat(64, 16)), std::invalid_argument);
}

TEST(GpiodPulseLine, MissingChipIsAClearError) {
  try {
    GpiodPulseLine line("gpiochip-that-does-not-exist", 3);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("gpiochip-that-does-not-exist"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldcast::io
