#pragma once
// A persistent pool of render workers (DESIGN.md §5). A job is a range of items (image columns)
// handed out in small chunks through one atomic counter; when a job's last chunk is taken, idle
// workers move on to the next submitted job at once, so consecutive frames overlap with no barrier.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace fieldcast::core {

/// Work for the pool: items [0, count) processed by `run(context, begin, end, worker)` in chunks.
/// The submitter owns the job and keeps it alive until RenderPool::wait() returns.
struct PoolJob {
  using RunFn = void (*)(void* context, int begin, int end, int worker) noexcept;
  RunFn run = nullptr;
  void* context = nullptr;
  int count = 0;  ///< number of items
  int chunk = 8;  ///< items taken at a time

  std::atomic<int> next{0};  ///< first item not yet taken
  std::atomic<int> done{0};  ///< items finished
  bool complete = false;     ///< guarded by the pool's mutex
  int users = 0;             ///< workers currently taking chunks; guarded by the pool's mutex
};

/// Persistent workers that take chunks of the oldest job with items left. Not copyable.
class RenderPool {
 public:
  /// `threads` ≤ 0: one per hardware thread. Starts the workers (allocates; not RT-safe).
  explicit RenderPool(int threads);
  ~RenderPool();
  RenderPool(const RenderPool&) = delete;
  RenderPool& operator=(const RenderPool&) = delete;

  int threads() const noexcept { return static_cast<int>(mWorkers.size()); }

  /// Queues `job` behind the jobs already submitted; returns at once. Up to kMaxQueued jobs may be
  /// in flight; a further submit waits for the oldest to be fully taken.
  void submit(PoolJob& job);
  /// Blocks until every item of `job` has been processed.
  void wait(PoolJob& job);

  static constexpr int kMaxQueued = 8;

 private:
  void workerLoop(int worker) noexcept;

  std::mutex mMutex;
  std::condition_variable mWork;  // a job was queued, or stop
  std::condition_variable mDone;  // a job completed, or the queue has room
  PoolJob* mQueue[kMaxQueued] = {};
  int mHead = 0;   // oldest job still handing out items
  int mCount = 0;  // jobs in the ring
  bool mStop = false;
  std::vector<std::thread> mWorkers;
};

}  // namespace fieldcast::core
