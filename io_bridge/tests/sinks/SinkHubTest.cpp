#include <io_bridge/SinkHub.h>
#include <io_bridge/Y4mSink.h>

#include "TestFields.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <condition_variable>
#include <mutex>
#include <thread>

namespace fieldcast::io {
namespace {

using testing::makeField;
using testing::testFormat;

// A sink that holds every consume() until released, and remembers what it saw.
struct GateState {
  std::mutex m;
  std::condition_variable cv;
  bool open = false;
  int entered = 0;  // consume() calls begun
  std::vector<std::uint64_t> seen;
  std::vector<std::uint8_t> firstBytes;
  bool closed = false;
};

class GateSink final : public FieldSink {
 public:
  explicit GateSink(std::shared_ptr<GateState> s) : mS(std::move(s)) {}
  std::string name() const override { return "gate"; }
  void open(const StreamFormat&) override {}
  SinkStatus consume(const Field& field) override {
    std::unique_lock lock(mS->m);
    ++mS->entered;
    mS->cv.notify_all();
    mS->cv.wait(lock, [&] { return mS->open; });
    mS->seen.push_back(field.fieldNumber);
    mS->firstBytes.push_back(field.image.bytes()[0]);
    return SinkStatus::Ok;
  }
  void close() override {
    std::lock_guard lock(mS->m);
    mS->closed = true;
  }

 private:
  std::shared_ptr<GateState> mS;
};

class FailingOpenSink final : public FieldSink {
 public:
  std::string name() const override { return "broken"; }
  void open(const StreamFormat&) override { throw std::runtime_error("/nonexistent/x: cannot open"); }
  SinkStatus consume(const Field&) override { return SinkStatus::Ok; }
  void close() override {}
};

TEST(SinkHub, SlowSinkNeverBlocksPublishAndDropsAreCounted) {
  const StreamFormat format = testFormat(64, 16);
  auto state = std::make_shared<GateState>();
  SinkHub hub(format, SinkHubOptions{3});
  hub.add(std::make_unique<GateSink>(state));
  hub.start();
  // The sink is stuck in its first consume(): publishing 20 fields must still return, with the
  // queue (3) plus the field in hand kept and the rest counted as dropped.
  hub.publish(makeField(format, 0));
  {
    // Wait until the worker holds field 0, so the count below is exact.
    std::unique_lock lock(state->m);
    state->cv.wait(lock, [&] { return state->entered == 1; });
  }
  for (std::uint64_t k = 1; k < 20; ++k) hub.publish(makeField(format, k));
  const auto before = hub.figures()[0];
  EXPECT_EQ(before.published, 20u);
  EXPECT_EQ(before.droppedFull, 17u);  // 3 slots: field 0 in hand, 2 waiting; 17 of 19 lost
  {
    std::lock_guard lock(state->m);
    state->open = true;
  }
  state->cv.notify_all();
  hub.stop();
  const auto after = hub.figures()[0];
  EXPECT_EQ(after.consumed + after.droppedFull, 20u);
  EXPECT_TRUE(state->closed);
  // The fields that got through arrive in order and intact.
  ASSERT_EQ(state->seen.size(), after.consumed);
  for (std::size_t i = 0; i < state->seen.size(); ++i) {
    if (i > 0) {
      EXPECT_GT(state->seen[i], state->seen[i - 1]);
    }
    EXPECT_EQ(state->firstBytes[i], makeField(format, state->seen[i]).image.bytes()[0]);
  }
}

TEST(SinkHub, WrongFieldsAreRejectedNotQueued) {
  const StreamFormat format = testFormat(64, 16);
  auto state = std::make_shared<GateState>();
  state->open = true;
  SinkHub hub(format);
  hub.add(std::make_unique<GateSink>(state));
  hub.start();
  Field wrong = makeField(testFormat(32, 16), 0);  // another width
  hub.publish(wrong);
  hub.publish(makeField(format, 1));
  hub.stop();
  const auto f = hub.figures()[0];
  EXPECT_EQ(f.rejected, 1u);
  EXPECT_EQ(f.consumed, 1u);
}

TEST(SinkHub, FailedOpenStopsStartWithTheReason) {
  SinkHub hub(testFormat(64, 16));
  auto state = std::make_shared<GateState>();
  hub.add(std::make_unique<GateSink>(state));
  hub.add(std::make_unique<FailingOpenSink>());
  try {
    hub.start();
    FAIL() << "start() should throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("sink 'broken': /nonexistent/x: cannot open"), std::string::npos) << e.what();
  }
}

TEST(SinkHub, BrokenPipeEndsThatSinkOnly) {
  const StreamFormat format = testFormat(64, 16);
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  auto state = std::make_shared<GateState>();
  state->open = true;
  SinkHub hub(format);
  hub.add(std::make_unique<Y4mSink>(Y4mSinkOptions{"/proc/self/fd/" + std::to_string(fds[1]), Y4mChroma::C420}));
  hub.add(std::make_unique<GateSink>(state));
  hub.start();      // the reader is still there while the header is written
  ::close(fds[0]);  // the consumer goes away
  for (std::uint64_t k = 0; k < 40; ++k) {
    hub.publish(makeField(format, k));
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  hub.stop();
  ::close(fds[1]);
  const auto figures = hub.figures();
  EXPECT_TRUE(figures[0].ended);
  EXPECT_NE(figures[0].endReason.find("broken pipe"), std::string::npos) << figures[0].endReason;
  EXPECT_FALSE(figures[1].ended);
  // The other sink went on: every field reached it or was counted as dropped (on a loaded machine
  // its queue of three can overflow; that is accounted for, not lost).
  EXPECT_EQ(figures[1].consumed + figures[1].droppedFull, 40u);
  EXPECT_GT(figures[1].consumed, 20u);
}

}  // namespace
}  // namespace fieldcast::io
