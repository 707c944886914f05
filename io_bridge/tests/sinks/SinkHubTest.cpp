#include <io_bridge/ImageFileSink.h>
#include <io_bridge/SinkHub.h>
#include <io_bridge/Y4mSink.h>

#include "TestFields.h"

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <new>
#include <optional>
#include <thread>

// spdlog's registry is built on first use; two sink workers logging their first drop at once would
// both build it, and ThreadSanitizer cannot see the guard inside the uninstrumented libspdlog. The
// service logs from its main thread before any worker starts; so does this test binary.
[[maybe_unused]] const bool gLoggerBuilt = spdlog::default_logger_raw() != nullptr;

// Counts heap allocations made by the thread that sets gCountAllocations (the "field thread").
namespace {
thread_local bool gCountAllocations = false;
std::atomic<int> gAllocations{0};
}  // namespace
void* operator new(std::size_t bytes) {
  if (gCountAllocations) gAllocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(bytes ? bytes : 1)) return p;
  throw std::bad_alloc();
}
// GCC 12 takes the replaced operator new for the library's and warns that free() does not match
// it; here both sides are malloc and free.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

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
  int corrupted = 0;  // fields whose bytes changed under the sink while it held them
  bool closed = false;
  std::optional<std::uint64_t> scheduleStart;  // what scheduleStarted() was told
  std::size_t seenAtScheduleStart = 0;         // fields consumed before it
  std::optional<std::uint64_t> scheduleEnd;    // what scheduleEnded() was told
  std::size_t seenAtScheduleEnd = 0;           // fields consumed before it
  bool closedAtScheduleEnd = false;
};

class GateSink final : public FieldSink {
 public:
  /// `wantEvery`: the sink wants only fields whose number is a multiple of it (FieldSink::wants).
  explicit GateSink(std::shared_ptr<GateState> s, std::string name = "gate", std::uint64_t wantEvery = 1)
      : mS(std::move(s)), mName(std::move(name)), mWantEvery(wantEvery) {}
  std::string name() const override { return mName; }
  void open(const StreamFormat& format) override { mFormat = format; }
  bool wants(const Field& field) const noexcept override { return field.fieldNumber % mWantEvery == 0; }
  SinkStatus consume(const Field& field) override {
    std::unique_lock lock(mS->m);
    ++mS->entered;
    mS->cv.notify_all();
    mS->cv.wait(lock, [&] { return mS->open; });
    mS->seen.push_back(field.fieldNumber);
    mS->firstBytes.push_back(field.image.bytes()[0]);
    if (!(field.image == makeField(mFormat, field.fieldNumber).image)) ++mS->corrupted;
    return SinkStatus::Ok;
  }
  void scheduleStarted(std::uint64_t firstField) override {
    std::lock_guard lock(mS->m);
    mS->scheduleStart = firstField;
    mS->seenAtScheduleStart = mS->seen.size();
  }
  void scheduleEnded(std::uint64_t firstFieldAfter) override {
    std::lock_guard lock(mS->m);
    mS->scheduleEnd = firstFieldAfter;
    mS->seenAtScheduleEnd = mS->seen.size();
    mS->closedAtScheduleEnd = mS->closed;
  }
  void close() override {
    std::lock_guard lock(mS->m);
    mS->closed = true;
  }

 private:
  std::shared_ptr<GateState> mS;
  std::string mName;
  std::uint64_t mWantEvery;
  StreamFormat mFormat;
};

// Waits until the gate's sink has begun its first consume() (it holds that field from then on).
void waitUntilHeld(GateState& s) {
  std::unique_lock lock(s.m);
  s.cv.wait(lock, [&] { return s.entered >= 1; });
}

// Lets the gate's sink finish every consume(), held or to come.
void openGate(GateState& s) {
  {
    std::lock_guard lock(s.m);
    s.open = true;
  }
  s.cv.notify_all();
}

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
  waitUntilHeld(*state);  // the worker holds field 0, so the count below is exact
  for (std::uint64_t k = 1; k < 20; ++k) hub.publish(makeField(format, k));
  const auto before = hub.figures()[0];
  EXPECT_EQ(before.published, 20u);
  EXPECT_EQ(before.droppedFull, 17u);  // 3 slots: field 0 in hand, 2 waiting; 17 of 19 lost
  openGate(*state);
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

// A sink that keeps one field in five (a still every N fields) and is stuck writing the first: the
// fields it passes over never fill its queue, so none it wants is lost.
TEST(SinkHub, UnwantedFieldsAreNeitherQueuedNorDropped) {
  const StreamFormat format = testFormat(64, 16);
  auto state = std::make_shared<GateState>();
  SinkHub hub(format, SinkHubOptions{4});
  hub.add(std::make_unique<GateSink>(state, "stills", 5));
  hub.start();
  hub.publish(makeField(format, 0));
  waitUntilHeld(*state);
  for (std::uint64_t k = 1; k < 20; ++k) hub.publish(makeField(format, k));
  const auto held = hub.figures()[0];
  EXPECT_EQ(held.published, 20u);
  EXPECT_EQ(held.passedOver, 16u);
  EXPECT_EQ(held.droppedFull, 0u);  // field 0 in hand, 5, 10 and 15 waiting: the queue's 4
  openGate(*state);
  hub.stop();
  EXPECT_EQ(state->seen, (std::vector<std::uint64_t>{0, 5, 10, 15}));
  EXPECT_EQ(state->corrupted, 0);
  EXPECT_EQ(hub.droppedTotal(), 0u);
  EXPECT_NE(hub.summary().find("16 passed over"), std::string::npos) << hub.summary();
}

// The image files' snapshot asked for from a third thread while the field thread publishes: the
// hub asks the sink (field thread) as its worker writes (worker thread); one file, of a field
// published after the request. Run under ThreadSanitizer by scripts/test.sh.
TEST(SinkHub, ASnapshotAskedFromAnotherThreadIsWrittenOnce) {
  const StreamFormat format = testFormat(64, 16);
  const auto dir = std::filesystem::temp_directory_path() / ("fieldcast_hub_snapshot_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  SinkHub hub(format, SinkHubOptions{3});
  auto owned = std::make_unique<ImageFileSink>(ImageFileSinkOptions{dir, 0, ImageFileFormat::Png, "snap"});
  ImageFileSink* images = owned.get();
  hub.add(std::move(owned));
  hub.start();
  std::uint64_t k = 0;
  for (; k < 50; ++k) hub.publish(makeField(format, k));  // none wanted: every_nth 0
  std::atomic<bool> asked{false};
  std::thread operatorThread([&] {
    images->requestSnapshot();
    asked.store(true, std::memory_order_release);
  });
  for (; !asked.load(std::memory_order_acquire); ++k) hub.publish(makeField(format, k));
  const std::uint64_t firstAfterAsking = k;  // the snapshot was pending when this one was asked
  for (; k < firstAfterAsking + 100; ++k) hub.publish(makeField(format, k));
  operatorThread.join();
  hub.stop();
  EXPECT_EQ(images->filesWritten(), 1u);
  const std::string written = images->lastPath().filename().string();
  const std::uint64_t number = std::stoull(written.substr(5, 8));  // snap_<8 digits>_<parity>.png
  EXPECT_GE(number, 50u) << written;
  EXPECT_LE(number, firstAfterAsking) << written;
  std::filesystem::remove_all(dir);
}

// One copy per publish is shared by all sinks: a stuck sink holding its fields must neither
// starve a fast sink of slots nor see its held fields overwritten.
TEST(SinkHub, AStuckSinkNeitherStarvesNorCorrupts) {
  const StreamFormat format = testFormat(64, 16);
  auto stuck = std::make_shared<GateState>();
  auto fast = std::make_shared<GateState>();
  fast->open = true;
  SinkHub hub(format, SinkHubOptions{3});
  hub.add(std::make_unique<GateSink>(stuck, "stuck"));
  hub.add(std::make_unique<GateSink>(fast, "fast"));
  hub.start();
  for (std::uint64_t k = 0; k < 50; ++k) {
    hub.publish(makeField(format, k));
    // let the fast sink finish each field, so none of its fields is dropped
    while (hub.figures()[1].consumed < k + 1) std::this_thread::yield();
  }
  openGate(*stuck);
  hub.stop();
  const auto figures = hub.figures();
  EXPECT_EQ(figures[1].consumed, 50u);
  EXPECT_EQ(figures[1].droppedFull, 0u);
  EXPECT_EQ(figures[0].consumed, 3u);  // fields 0, 1, 2 held the whole time
  EXPECT_EQ(stuck->corrupted, 0);
  EXPECT_EQ(fast->corrupted, 0);
}

TEST(SinkHub, TheScheduleReachesEachSinkBeforeItsFirstFieldAndAfterItsLast) {
  const StreamFormat format = testFormat(64, 16);
  auto held = std::make_shared<GateState>();  // holds the fields until the schedule has ended
  auto told = std::make_shared<GateState>();
  told->open = true;
  auto untold = std::make_shared<GateState>();
  untold->open = true;
  {
    SinkHub hub(format, SinkHubOptions{3});
    hub.add(std::make_unique<GateSink>(held, "held"));
    hub.add(std::make_unique<GateSink>(told, "told"));
    hub.start();
    hub.beginSchedule(2);
    for (std::uint64_t k = 4; k < 7; ++k) hub.publish(makeField(format, k));
    hub.endSchedule(9);
    openGate(*held);
    hub.stop();
  }
  for (const auto& s : {held, told}) {
    EXPECT_EQ(s->scheduleStart, 2u);
    EXPECT_EQ(s->seenAtScheduleStart, 0u);
    EXPECT_EQ(s->scheduleEnd, 9u);
    EXPECT_EQ(s->seenAtScheduleEnd, 3u);
    EXPECT_FALSE(s->closedAtScheduleEnd);
    EXPECT_TRUE(s->closed);
  }
  // A run stopped rather than ended by its schedule says nothing.
  SinkHub hub(format, SinkHubOptions{3});
  hub.add(std::make_unique<GateSink>(untold, "untold"));
  hub.start();
  hub.publish(makeField(format, 0));
  hub.stop();
  EXPECT_FALSE(untold->scheduleStart.has_value());
  EXPECT_FALSE(untold->scheduleEnd.has_value());
  EXPECT_TRUE(untold->closed);
}

TEST(SinkHub, PublishNeverAllocates) {
  const StreamFormat format = testFormat(720, 486);
  auto slow = std::make_shared<GateState>();  // stuck: its queue fills, so drops happen too
  auto fast = std::make_shared<GateState>();
  fast->open = true;
  SinkHub hub(format);
  hub.add(std::make_unique<GateSink>(slow, "slow"));
  hub.add(std::make_unique<GateSink>(fast, "fast"));
  hub.start();
  std::vector<Field> fields;
  for (std::uint64_t k = 0; k < 8; ++k) fields.push_back(makeField(format, k));
  Field wrong = makeField(testFormat(64, 16), 0);
  gAllocations = 0;
  gCountAllocations = true;
  for (int i = 0; i < 200; ++i) hub.publish(fields[static_cast<std::size_t>(i) % fields.size()]);
  hub.publish(wrong);
  gCountAllocations = false;
  EXPECT_EQ(gAllocations.load(), 0);
  openGate(*slow);
  hub.stop();
}

// Records the scheduling policy its worker runs under.
class PolicySink final : public FieldSink {
 public:
  explicit PolicySink(int* policy) : mPolicy(policy) {}
  std::string name() const override { return "policy"; }
  void open(const StreamFormat&) override {
    sched_param p{};
    pthread_getschedparam(pthread_self(), mPolicy, &p);
  }
  SinkStatus consume(const Field&) override { return SinkStatus::Ok; }
  void close() override {}

 private:
  int* mPolicy;
};

TEST(SinkHub, RealtimeWorkerWhenGrantedAndSaysSo) {
  int policy = -1;
  SinkHub hub(testFormat(64, 16));
  hub.add(std::make_unique<PolicySink>(&policy), SinkWorkerOptions{10});
  hub.start();  // runs whether or not the system grants SCHED_FIFO
  const bool realtime = hub.figures()[0].realtime;
  hub.stop();
  EXPECT_EQ(policy == SCHED_FIFO, realtime);
  EXPECT_THROW(hub.add(std::make_unique<PolicySink>(&policy), SinkWorkerOptions{120}), std::logic_error);
  SinkHub other(testFormat(64, 16));
  EXPECT_THROW(other.add(std::make_unique<PolicySink>(&policy), SinkWorkerOptions{120}), std::invalid_argument);
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
    // wait for the healthy sink, so that none of its fields is dropped on a loaded machine
    while (hub.figures()[1].consumed < k + 1) std::this_thread::yield();
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
