// evdev decoding fed through a pipe in place of /dev/input/eventN: recorded struct input_event
// streams in the kernel's binary layout, including a buffer overrun (SYN_DROPPED) and its resync.
#include <io_bridge/EvdevDecoder.h>

#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstring>
#include <vector>

namespace fieldcast::io {
namespace {

using namespace std::chrono_literals;

input_event ev(long sec, long usec, std::uint16_t type, std::uint16_t code, std::int32_t value) {
  input_event e{};
  e.input_event_sec = sec;
  e.input_event_usec = usec;
  e.type = type;
  e.code = code;
  e.value = value;
  return e;
}

class Pipe {
 public:
  Pipe() {
    EXPECT_EQ(::pipe2(mFds, O_CLOEXEC), 0);
    ::fcntl(mFds[0], F_SETFL, O_NONBLOCK);
  }
  ~Pipe() {
    ::close(mFds[0]);
    closeWriter();
  }
  int reader() const { return mFds[0]; }
  void write(const std::vector<input_event>& events) { writeBytes(events.data(), events.size() * sizeof(input_event)); }
  void writeBytes(const void* data, std::size_t n) { ASSERT_EQ(::write(mFds[1], data, n), static_cast<ssize_t>(n)); }
  void closeWriter() {
    if (mFds[1] >= 0) ::close(mFds[1]);
    mFds[1] = -1;
  }

 private:
  int mFds[2]{-1, -1};
};

// The device state a real device would report through EVIOCGABS/EVIOCGKEY.
class ScriptedState final : public EvdevStateQuery {
 public:
  std::vector<EvdevCodeValue> state;
  int queries = 0;
  bool currentState(std::vector<EvdevCodeValue>& out) override {
    ++queries;
    out.insert(out.end(), state.begin(), state.end());
    return true;
  }
};

std::vector<InputEvent> readAll(EvdevStreamReader& reader) {
  std::vector<InputEvent> out;
  while (reader.read(out, 0ms) == ReadResult::Events) {
  }
  return out;
}

TEST(EvdevDecoder, FramesCarryTheKernelTimestamp) {
  Pipe pipe;
  ScriptedState state;
  EvdevStreamReader reader(pipe.reader(), &state);
  pipe.write({ev(12, 345678, EV_ABS, ABS_X, 100), ev(12, 345678, EV_ABS, ABS_Y, -200),
              ev(12, 345678, EV_ABS, ABS_THROTTLE, 7), ev(12, 345678, EV_SYN, SYN_REPORT, 0)});
  const auto out = readAll(reader);
  ASSERT_EQ(out.size(), 4u);
  const std::int64_t t = 12'345'678'000;
  EXPECT_EQ(out[0], (InputEvent{t, usages::kX, 100, InputEventType::Value}));
  EXPECT_EQ(out[1], (InputEvent{t, usages::kY, -200, InputEventType::Value}));
  EXPECT_EQ(out[2], (InputEvent{t, usages::kThrottle, 7, InputEventType::Value}));
  EXPECT_EQ(out[3], (InputEvent{t, 0, 0, InputEventType::Sync}));
  EXPECT_EQ(reader.decoder().frames(), 1u);
}

TEST(EvdevDecoder, ButtonsAndHatsAsHidUsages) {
  Pipe pipe;
  EvdevStreamReader reader(pipe.reader(), nullptr);
  pipe.write({ev(1, 0, EV_KEY, BTN_TRIGGER, 1), ev(1, 0, EV_KEY, BTN_TRIGGER_HAPPY1, 1), ev(1, 0, EV_KEY, BTN_EAST, 1),
              ev(1, 0, EV_KEY, KEY_A, 1), ev(1, 0, EV_ABS, ABS_HAT0Y, -1), ev(1, 0, EV_SYN, SYN_REPORT, 0),
              ev(1, 10, EV_ABS, ABS_HAT0X, 1), ev(1, 10, EV_SYN, SYN_REPORT, 0), ev(1, 20, EV_KEY, BTN_TRIGGER, 2),
              ev(1, 20, EV_SYN, SYN_REPORT, 0),  // autorepeat: ignored
              ev(1, 30, EV_ABS, ABS_HAT0X, -1), ev(1, 30, EV_ABS, ABS_HAT0Y, 1), ev(1, 30, EV_SYN, SYN_REPORT, 0)});
  const auto out = readAll(reader);
  std::vector<InputEvent> values;
  for (const auto& e : out) {
    if (e.type == InputEventType::Value) values.push_back(e);
  }
  ASSERT_EQ(values.size(), 6u);
  EXPECT_EQ(values[0].usage, usages::button(1));
  EXPECT_EQ(values[1].usage, usages::button(17));
  EXPECT_EQ(values[2].usage, usages::button(2));  // BTN_EAST is gamepad button 2
  EXPECT_EQ(values[3].usage, usages::kHatSwitch);
  EXPECT_EQ(values[3].value, 0);  // up
  EXPECT_EQ(values[4].value, 1);  // up-right
  EXPECT_EQ(values[5].value, 5);  // down-left: one hat event for a frame that moved both axes
  EXPECT_EQ(hatFromAxes(-1, 1), 5);
  EXPECT_EQ(hatFromAxes(0, 0), kHatCentred);
}

TEST(EvdevDecoder, SynDroppedDiscardsTheFrameAndResyncs) {
  Pipe pipe;
  ScriptedState state;
  EvdevStreamReader reader(pipe.reader(), &state);
  pipe.write({ev(2, 0, EV_ABS, ABS_X, 10), ev(2, 0, EV_ABS, ABS_Y, 20), ev(2, 0, EV_KEY, BTN_THUMB, 1),
              ev(2, 0, EV_SYN, SYN_REPORT, 0)});
  auto out = readAll(reader);
  ASSERT_EQ(out.size(), 4u);

  // The kernel's buffer overflowed: X=11 arrived, then SYN_DROPPED, then stale events.
  state.state = {{EV_ABS, ABS_X, 55}, {EV_ABS, ABS_Y, 20}, {EV_KEY, BTN_THUMB, 0}, {EV_KEY, BTN_TRIGGER, 1}};
  pipe.write({ev(3, 0, EV_ABS, ABS_X, 11), ev(3, 0, EV_SYN, SYN_DROPPED, 0), ev(3, 5, EV_ABS, ABS_Y, 999),
              ev(3, 5, EV_KEY, BTN_BASE, 1), ev(3, 5, EV_SYN, SYN_REPORT, 0), ev(3, 9, EV_ABS, ABS_Z, 4),
              ev(3, 9, EV_SYN, SYN_REPORT, 0)});
  out = readAll(reader);
  EXPECT_EQ(state.queries, 1);
  EXPECT_EQ(reader.decoder().droppedBursts(), 1u);
  // The resync frame: only what differs from what we had, stamped with the closing SYN_REPORT.
  const std::int64_t t = 3'000'005'000;
  ASSERT_EQ(out.size(), 6u);
  EXPECT_EQ(out[0], (InputEvent{t, usages::kX, 55, InputEventType::Value}));
  EXPECT_EQ(out[1], (InputEvent{t, usages::button(2), 0, InputEventType::Value}));
  EXPECT_EQ(out[2], (InputEvent{t, usages::button(1), 1, InputEventType::Value}));
  EXPECT_EQ(out[3].type, InputEventType::Sync);
  // Then decoding goes on normally.
  EXPECT_EQ(out[4], (InputEvent{3'000'009'000, usages::kZ, 4, InputEventType::Value}));
}

TEST(EvdevDecoder, PartialEventsAcrossReadsAndEndOfStream) {
  Pipe pipe;
  EvdevStreamReader reader(pipe.reader(), nullptr);
  const std::vector<input_event> events{ev(5, 0, EV_ABS, ABS_RZ, -3), ev(5, 0, EV_SYN, SYN_REPORT, 0)};
  std::vector<std::uint8_t> bytes(events.size() * sizeof(input_event));
  std::memcpy(bytes.data(), events.data(), bytes.size());
  pipe.writeBytes(bytes.data(), 10);
  std::vector<InputEvent> out;
  EXPECT_EQ(reader.read(out, 0ms), ReadResult::Timeout);
  pipe.writeBytes(bytes.data() + 10, bytes.size() - 10);
  EXPECT_EQ(reader.read(out, 0ms), ReadResult::Events);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].value, -3);
  EXPECT_EQ(reader.read(out, 0ms), ReadResult::Timeout);
  pipe.closeWriter();
  EXPECT_EQ(reader.read(out, 10ms), ReadResult::End);
}

TEST(EvdevDecoder, QueryNowGivesTheStateAtOpen) {
  ScriptedState state;
  state.state = {{EV_ABS, ABS_X, 0}, {EV_ABS, ABS_Y, 512}};
  EvdevDecoder decoder(&state);
  std::vector<InputEvent> out;
  decoder.queryNow(77, out);
  ASSERT_EQ(out.size(), 3u);  // X = 0 is reported too: it is a position, not "no data"
  EXPECT_EQ(out[0].value, 0);
  EXPECT_EQ(out[1].value, 512);
}

}  // namespace
}  // namespace fieldcast::io
