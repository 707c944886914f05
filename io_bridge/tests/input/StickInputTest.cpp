// The input thread's behaviour in virtual time: publication, device loss with decay, reconnection
// with backoff, and record → replay giving bit-identical ControlState sequences.
#include <io_bridge/InputRecording.h>
#include <io_bridge/StickInput.h>

#include "FakeInputSource.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace fieldcast::io {
namespace {

using namespace std::chrono_literals;
using namespace usages;
using testing::FakeInputSource;
using testing::frame;
using testing::plainStick;

std::filesystem::path tempFile(const char* name) {
  return std::filesystem::temp_directory_path() / (std::string(name) + "-" + std::to_string(::getpid()));
}

std::deque<std::vector<InputEvent>> flight() {
  std::deque<std::vector<InputEvent>> f;
  f.push_back(frame(1'000'000, {{kX, 512}, {kY, 512}, {kRz, 512}, {kThrottle, 255}}));
  for (int i = 1; i <= 50; ++i) {
    f.push_back(frame(1'000'000 + i * 1'000'000,
                      {{kX, 512 + i * 10}, {kY, 512 - i * 7}, {button(static_cast<std::uint16_t>(1 + i % 8)), i % 2}}));
  }
  f.push_back(frame(60'000'000, {{kHatSwitch, 3}, {kThrottle, 17}}));
  return f;
}

TEST(StickInput, PublishesEachFrame) {
  VirtualClock clock;
  auto factory = [] { return std::make_unique<FakeInputSource>(plainStick(), flight(), ReadResult::End); };
  StickInputOptions options;
  options.reconnect = false;
  StickInput input(factory, StickProfile::generic(), options, clock);
  EXPECT_EQ(input.latest().health, InputHealth::NoDevice);
  EXPECT_DOUBLE_EQ(input.controlsAt(clock.now()).roll, 0.0);
  ASSERT_TRUE(input.step());  // connect
  ASSERT_TRUE(input.step());  // first frame
  EXPECT_EQ(input.latest().health, InputHealth::Live);
  EXPECT_DOUBLE_EQ(input.latest().throttle, 0.0);  // 255 on an inverted lever
  while (input.step()) {
  }
  EXPECT_EQ(input.stats().frames, 52u);
  EXPECT_EQ(input.latest().health, InputHealth::Holding);  // the source ended
}

// A device that never stops: X and Y always equal, so a torn read would show roll != pitch.
class EndlessStick final : public InputSource {
 public:
  const DeviceDescription& description() const noexcept override { return mDevice; }
  ReadResult read(std::vector<InputEvent>& out, Nanoseconds) override {
    ++mV;
    const std::int32_t v = static_cast<std::int32_t>(mV % 1024);
    out.push_back({mV, kX, v, InputEventType::Value});
    out.push_back({mV, kY, v, InputEventType::Value});
    out.push_back({mV, 0, 0, InputEventType::Sync});
    return ReadResult::Events;
  }

 private:
  DeviceDescription mDevice = plainStick();
  std::int64_t mV = 0;
};

TEST(StickInput, TheFieldThreadReadsWhileTheInputThreadWrites) {
  SystemClock clock;
  StickInput input([] { return std::make_unique<EndlessStick>(); }, StickProfile::generic(), StickInputOptions{},
                   clock);
  input.start();
  int torn = 0;
  std::uint64_t reads = 0;
  while (input.stats().frames < 20000 && reads < 50'000'000) {
    const ControlState s = input.controlsAt(clock.now());
    if (s.roll != s.pitch) ++torn;
    ++reads;
  }
  input.stop();
  EXPECT_EQ(torn, 0);
  EXPECT_GE(input.stats().frames, 20000u);
}

TEST(StickInput, LossHoldsAndDecaysThenReconnectsWithBackoff) {
  VirtualClock clock(TimePoint{10s});
  int opens = 0;
  bool plugged = true;
  auto factory = [&]() -> std::unique_ptr<InputSource> {
    ++opens;
    if (!plugged) throw std::runtime_error("no such device");
    std::deque<std::vector<InputEvent>> frames;
    frames.push_back(frame(1, {{kX, 1023}, {kY, 0}, {kRz, 512}, {kThrottle, 0}, {button(1), 1}, {kHatSwitch, 2}}));
    return std::make_unique<FakeInputSource>(plainStick(), frames, ReadResult::Lost);
  };
  StickProfile profile = StickProfile::generic();
  profile.lossDecayS = 2.0;
  StickInputOptions options;
  options.backoffMin = 100ms;
  options.backoffMax = 400ms;
  StickInput input(factory, profile, options, clock);
  input.step();  // connect
  input.step();  // the frame
  EXPECT_DOUBLE_EQ(input.latest().roll, 1.0);
  plugged = false;
  input.step();  // read → Lost
  const ControlState held = input.latest();
  EXPECT_EQ(held.health, InputHealth::Holding);
  EXPECT_EQ(held.lostAt, TimePoint{10s});
  EXPECT_EQ(input.stats().losses, 1u);
  // Decay: half way after 1 s of 2 s, neutral after 2 s; buttons and hat released at once;
  // throttle held (the profile's default policy).
  const ControlState half = input.controlsAt(TimePoint{11s});
  EXPECT_DOUBLE_EQ(half.roll, 0.5);
  EXPECT_DOUBLE_EQ(half.pitch, -0.5);
  EXPECT_EQ(half.buttons, 0u);
  EXPECT_EQ(half.hat, kHatCentred);
  EXPECT_DOUBLE_EQ(half.throttle, 1.0);
  EXPECT_DOUBLE_EQ(input.controlsAt(TimePoint{13s}).roll, 0.0);

  // Reconnection attempts at +100 ms, then +200 ms, +400 ms, +400 ms (capped).
  std::vector<TimePoint> attempts;
  int seen = opens;
  while (attempts.size() < 4) {
    input.step();
    if (opens != seen) {
      attempts.push_back(clock.now());
      seen = opens;
    }
  }
  EXPECT_EQ(attempts[0], TimePoint{10s + 100ms});
  EXPECT_EQ(attempts[1], TimePoint{10s + 300ms});
  EXPECT_EQ(attempts[2], TimePoint{10s + 700ms});
  EXPECT_EQ(attempts[3], TimePoint{10s + 1100ms});
  EXPECT_EQ(input.stats().failedOpens, 4u);
  plugged = true;
  while (input.stats().connects < 2) input.step();
  input.step();
  EXPECT_EQ(input.latest().health, InputHealth::Live);
  EXPECT_DOUBLE_EQ(input.controlsAt(TimePoint{100s}).roll, 1.0);  // live: no decay
}

TEST(StickInput, NeutralThrottlePolicy) {
  ControlState held;
  held.health = InputHealth::Holding;
  held.lostAt = TimePoint{0s};
  held.throttle = 1.0;
  StickProfile p = StickProfile::generic();
  p.throttleOnLoss = ThrottleOnLoss::Neutral;
  p.defaultThrottle = 0.2;
  p.lossDecayS = 1.0;
  EXPECT_NEAR(decayToward(held, TimePoint{500ms}, p).throttle, 0.6, 1e-12);
  EXPECT_DOUBLE_EQ(decayToward(held, TimePoint{5s}, p).throttle, 0.2);
  p.lossDecayS = 0.0;  // no decay time: neutral at once
  EXPECT_DOUBLE_EQ(decayToward(held, TimePoint{0s}, p).throttle, 0.2);
}

// Bit-identical, field by field (memcmp would also compare padding bytes, which carry nothing).
bool bitIdentical(const ControlState& a, const ControlState& b) {
  const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
  return a.time == b.time && bits(a.roll) == bits(b.roll) && bits(a.pitch) == bits(b.pitch) &&
         bits(a.yaw) == bits(b.yaw) && bits(a.throttle) == bits(b.throttle) && a.buttons == b.buttons &&
         a.hat == b.hat && a.health == b.health && a.lostAt == b.lostAt;
}

std::vector<ControlState> run(StickInput& input) {
  std::vector<ControlState> states;
  std::uint64_t version = 0;
  while (input.step()) {
    if (input.stats().frames != version) {
      version = input.stats().frames;
      states.push_back(input.latest());
    }
  }
  return states;
}

TEST(InputRecording, ReplayGivesBitIdenticalControlStates) {
  const auto path = tempFile("fieldcast-replay-test.rec");
  VirtualClock clock;
  StickInputOptions options;
  options.reconnect = false;
  options.recordPath = path;
  StickProfile profile = StickProfile::generic();
  profile.axis(AxisRole::Roll).expo = 0.37;  // non-trivial arithmetic on the way
  std::vector<ControlState> live;
  {
    StickInput input([] { return std::make_unique<FakeInputSource>(plainStick(), flight(), ReadResult::Lost); },
                     profile, options, clock);
    live = run(input);
    input.stop();
  }
  ASSERT_EQ(live.size(), 52u);

  const InputRecording rec = readInputRecording(path);
  EXPECT_EQ(rec.device.name, "Test Stick");
  EXPECT_EQ(rec.device.controls, plainStick().controls);
  EXPECT_EQ(rec.events.back().type, InputEventType::DeviceLost);

  StickInputOptions replayOptions;
  replayOptions.reconnect = false;
  StickInput replay([&] { return std::make_unique<ReplaySource>(path, ReplayPacing::AsFastAsPossible, clock); },
                    profile, replayOptions, clock);
  const std::vector<ControlState> replayed = run(replay);
  ASSERT_EQ(replayed.size(), live.size());
  for (std::size_t i = 0; i < live.size(); ++i) {
    EXPECT_TRUE(bitIdentical(live[i], replayed[i])) << "frame " << i;
  }
  std::filesystem::remove(path);
}

TEST(InputRecording, RealTimePacingKeepsTheSpacing) {
  InputRecording rec;
  rec.device = plainStick();
  for (const auto& f : {frame(5'000, {{kX, 1}}), frame(25'000'000, {{kX, 2}}), frame(75'000'000, {{kX, 3}})}) {
    rec.events.insert(rec.events.end(), f.begin(), f.end());
  }
  VirtualClock clock(TimePoint{1s});
  ReplaySource source(rec, ReplayPacing::RealTime, clock);
  std::vector<InputEvent> out;
  EXPECT_EQ(source.read(out, 10ms), ReadResult::Events);
  EXPECT_EQ(out.back().tNs, 1'000'000'000);  // moved to the replay clock
  out.clear();
  EXPECT_EQ(source.read(out, 10ms), ReadResult::Timeout);  // the next frame is 25 ms later
  EXPECT_EQ(source.read(out, 10ms), ReadResult::Timeout);
  EXPECT_EQ(source.read(out, 10ms), ReadResult::Events);
  EXPECT_EQ(clock.now(), TimePoint{1s} + Nanoseconds{25'000'000 - 5'000});
  EXPECT_EQ(out.back().tNs, clock.now().time_since_epoch().count());
  out.clear();
  EXPECT_EQ(source.read(out, 1s), ReadResult::Events);
  EXPECT_EQ(source.read(out, 1s), ReadResult::End);
}

TEST(InputRecording, MalformedFilesNameTheLine) {
  const auto path = tempFile("fieldcast-bad.rec");
  auto errorOf = [&](const char* text) {
    std::ofstream(path) << text;
    try {
      (void)readInputRecording(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(errorOf("hello\n").find(":1: expected \"fieldcast-input 1\""), std::string::npos);
  EXPECT_NE(errorOf("fieldcast-input 1\nv 12 zz 3\n").find(":2: expected \"v <t_ns> <usage hex> <value>\""),
            std::string::npos);
  EXPECT_NE(errorOf("fieldcast-input 1\n# note\nbogus 1\n").find(":3: unknown record \"bogus\""), std::string::npos);
  EXPECT_NE(errorOf("fieldcast-input 1\ncontrol 00010030 knob 0 1\n").find(":2: control kind"), std::string::npos);
  EXPECT_NE(errorOf("").find("empty file"), std::string::npos);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace fieldcast::io
