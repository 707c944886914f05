#include <ig_core/RenderPool.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace fieldcast::core {
namespace {

struct Marks {
  std::vector<int> hits;
};
void mark(void* context, int begin, int end, int) noexcept {
  auto* m = static_cast<Marks*>(context);
  for (int k = begin; k < end; ++k) ++m->hits[static_cast<std::size_t>(k)];
}

TEST(RenderPool, EveryItemOfEveryOverlappingJobRunsExactlyOnce) {
  RenderPool pool(3);
  constexpr int kJobs = 20;
  std::vector<Marks> marks(kJobs);
  std::vector<PoolJob> jobs(kJobs);
  for (int n = 0; n < kJobs; ++n) {
    marks[static_cast<std::size_t>(n)].hits.assign(static_cast<std::size_t>(97 + n), 0);
    PoolJob& job = jobs[static_cast<std::size_t>(n)];
    job.run = &mark;
    job.context = &marks[static_cast<std::size_t>(n)];
    job.count = 97 + n;
    job.chunk = 3;
  }
  // Keep up to four jobs in flight so workers roll from one into the next.
  for (int n = 0; n < kJobs; ++n) {
    pool.submit(jobs[static_cast<std::size_t>(n)]);
    if (n >= 3) pool.wait(jobs[static_cast<std::size_t>(n - 3)]);
  }
  for (int n = 0; n < kJobs; ++n) pool.wait(jobs[static_cast<std::size_t>(n)]);
  for (const Marks& m : marks) {
    for (const int h : m.hits) ASSERT_EQ(h, 1);
  }
}

// RenderPool.h promises no barrier between jobs: once a job's last chunk is taken, idle workers
// move on to the next. Job A's first item holds its worker until the test releases it; its other
// item is quick, so the second worker finds A's items all taken and must take job B, which then
// completes while A is still running. With a barrier between jobs B would start only after A's
// first item gave up waiting (after 60 s), and the test fails.
struct Overlap {
  std::atomic<bool> release{false};
  std::atomic<bool> aHeldItemDone{false};
  std::atomic<int> bItems{0};
};
void holdFirstItem(void* context, int begin, int, int) noexcept {
  auto* o = static_cast<Overlap*>(context);
  if (begin != 0) return;
  // Bounded, so a pool with a barrier fails the test instead of hanging it.
  for (int n = 0; n < 60'000 && !o->release.load(); ++n) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  o->aHeldItemDone.store(true);
}
void countItem(void* context, int, int, int) noexcept { static_cast<Overlap*>(context)->bItems.fetch_add(1); }

TEST(RenderPool, NextJobRunsWhileTheLastChunkOfThePreviousIsStillRunning) {
  RenderPool pool(2);
  Overlap o;
  PoolJob a;
  a.run = &holdFirstItem;
  a.context = &o;
  a.count = 2;
  a.chunk = 1;
  PoolJob b;
  b.run = &countItem;
  b.context = &o;
  b.count = 4;
  b.chunk = 1;
  pool.submit(a);
  pool.submit(b);
  pool.wait(b);
  const bool aStillRunning = !o.aHeldItemDone.load();
  o.release.store(true);
  pool.wait(a);
  EXPECT_EQ(o.bItems.load(), 4);
  EXPECT_TRUE(aStillRunning) << "job B waited for job A to finish: a barrier between frames";
  EXPECT_TRUE(a.complete);
}

TEST(RenderPool, EmptyJobCompletesAtOnce) {
  RenderPool pool(1);
  PoolJob job;
  job.run = &mark;
  job.count = 0;
  pool.submit(job);
  pool.wait(job);
  EXPECT_TRUE(job.complete);
}

}  // namespace
}  // namespace fieldcast::core
