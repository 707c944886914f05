#include <ig_core/RenderPool.h>

#include <gtest/gtest.h>

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
