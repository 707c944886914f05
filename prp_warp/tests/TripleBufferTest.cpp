// The renderer → PRP hand-over: newest complete value wins, neither side waits (run under TSan
// with FIELDCAST_SANITIZE=thread to check the ordering).
#include <prp_warp/TripleBuffer.h>

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
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
  // Many frames, the consumer taking at irregular moments (sometimes several publishes apart,
  // sometimes twice in a row): every frame it takes is whole (its pixels carry its number), newer
  // than the one before, and the newest published at that moment; at the end it holds the last.
  Frame initial;
  initial.image.resize(8, 8, PixelFormat::Grey8);
  FrameHandover handover(initial);
  constexpr std::uint64_t kFrames = 1000;
  std::uint64_t lastTaken = 0;
  std::uint64_t taken = 0;
  for (std::uint64_t n = 1; n <= kFrames; ++n) {
    Frame& back = handover.back();
    back.frameNumber = n;
    for (std::uint8_t& b : back.image.bytes()) b = static_cast<std::uint8_t>(n * 7 + 3);
    handover.publish();
    if (n % 7 == 0 || n % 11 == 0 || n % 13 == 0) {
      ASSERT_TRUE(handover.update()) << "frame " << n << " was published but not taken";
      const Frame& f = handover.front();
      EXPECT_EQ(f.frameNumber, n) << "not the newest published";
      EXPECT_GT(f.frameNumber, lastTaken) << "out of order";
      for (const std::uint8_t b : f.image.bytes()) ASSERT_EQ(b, static_cast<std::uint8_t>(f.frameNumber * 7 + 3));
      lastTaken = f.frameNumber;
      ++taken;
      EXPECT_FALSE(handover.update()) << "took frame " << n << " twice";
    }
  }
  const Frame& last = handover.newest();
  EXPECT_EQ(last.frameNumber, kFrames);
  for (const std::uint8_t b : last.image.bytes()) ASSERT_EQ(b, static_cast<std::uint8_t>(kFrames * 7 + 3));
  EXPECT_GT(taken, 200u);
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
    // Read `done` before trying: once the producer is known finished, an update() that finds
    // nothing new means the last value was already taken, and every taken value was checked.
    const bool finished = done.load(std::memory_order_acquire);
    if (tb.update()) {
      const Payload& p = tb.front();
      for (std::uint64_t w : p.words) torn |= w != p.number;
      backwards |= p.number <= last;
      last = p.number;
      ++taken;
    } else if (finished) {
      break;
    }
  }
  producer.join();
  EXPECT_FALSE(torn);
  EXPECT_FALSE(backwards) << "a value older than (or the same as) the one before was taken";
  EXPECT_EQ(last, kCount) << "the consumer did not end with the last value published";
  EXPECT_EQ(tb.front().number, kCount);
  EXPECT_GT(taken, 0u);
}

}  // namespace
}  // namespace fieldcast::warp
