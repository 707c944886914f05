#include <fieldcast/SeqLock.h>

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

namespace fieldcast {
namespace {

// Every field holds the same number, so a torn read (half old, half new) is detectable.
struct Wide {
  std::uint64_t a, b, c, d, e;
  std::uint32_t f;
};

TEST(SeqLock, StoresAndLoads) {
  SeqLock<Wide> cell(Wide{1, 1, 1, 1, 1, 1});
  EXPECT_EQ(cell.load().c, 1u);
  cell.store(Wide{7, 7, 7, 7, 7, 7});
  EXPECT_EQ(cell.load().f, 7u);
  EXPECT_EQ(cell.version(), 2u);
}

TEST(SeqLock, ReadersNeverSeeATornValue) {
  SeqLock<Wide> cell;
  std::atomic<bool> done{false};
  std::atomic<int> torn{0};
  std::thread reader([&] {
    std::uint64_t last = 0;
    while (!done.load()) {
      const Wide w = cell.load();
      if (w.a != w.b || w.b != w.c || w.c != w.d || w.d != w.e || w.e != w.f) torn.fetch_add(1);
      if (w.a < last) torn.fetch_add(1);  // values only go forward
      last = w.a;
    }
  });
  for (std::uint32_t i = 1; i <= 200000; ++i) cell.store(Wide{i, i, i, i, i, i});
  done = true;
  reader.join();
  EXPECT_EQ(torn.load(), 0);
  EXPECT_EQ(cell.load().a, 200000u);
}

}  // namespace
}  // namespace fieldcast
