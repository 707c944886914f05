// The renderer → PRP hand-over: newest complete value wins, neither side waits (run under TSan
// with FIELDCAST_SANITIZE=thread to check the ordering).
#include <prp_warp/TripleBuffer.h>

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <thread>

namespace fieldcast::warp {
namespace {

TEST(TripleBuffer, TheNewestPublishedValueWins) {
  TripleBuffer<int> tb(0);
  EXPECT_FALSE(tb.update());
  EXPECT_FALSE(tb.hasTaken());
  tb.back() = 1;
  tb.publish();
  tb.back() = 2;
  tb.publish();  // 1 was never taken: overwritten
  EXPECT_EQ(tb.newest(), 2);
  EXPECT_TRUE(tb.hasTaken());
  EXPECT_FALSE(tb.update());  // nothing newer: front stays
  EXPECT_EQ(tb.front(), 2);
  tb.back() = 3;
  tb.publish();
  EXPECT_EQ(tb.front(), 2);  // unchanged until the consumer asks
  EXPECT_EQ(tb.newest(), 3);
}

TEST(TripleBuffer, FramesAreHandedOverWholeAndInOrder) {
  Frame initial;
  initial.image.resize(8, 8, PixelFormat::Grey8);
  FrameHandover handover(initial);
  handover.back().frameNumber = 7;
  handover.back().image.bytes()[0] = 42;
  handover.publish();
  const Frame& f = handover.newest();
  EXPECT_EQ(f.frameNumber, 7u);
  EXPECT_EQ(f.image.bytes()[0], 42);
}

TEST(TripleBuffer, ConcurrentProducerAndConsumerSeeOnlyCompleteIncreasingValues) {
  struct Payload {
    std::uint64_t number = 0;
    std::array<std::uint64_t, 64> words{};  // all equal to number when complete
  };
  TripleBuffer<Payload> tb;
  constexpr std::uint64_t kCount = 200'000;
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (std::uint64_t n = 1; n <= kCount; ++n) {
      Payload& p = tb.back();
      p.number = n;
      p.words.fill(n);
      tb.publish();
    }
    done.store(true, std::memory_order_release);
  });
  std::uint64_t last = 0, taken = 0;
  bool torn = false, backwards = false;
  for (;;) {
    const bool finished = done.load(std::memory_order_acquire);
    if (tb.update()) {
      const Payload& p = tb.front();
      for (std::uint64_t w : p.words) torn |= w != p.number;
      backwards |= p.number <= last;
      last = p.number;
      ++taken;
    }
    if (finished && !tb.update()) break;
  }
  producer.join();
  EXPECT_FALSE(torn);
  EXPECT_FALSE(backwards);
  EXPECT_GT(taken, 0u);
}

}  // namespace
}  // namespace fieldcast::warp
