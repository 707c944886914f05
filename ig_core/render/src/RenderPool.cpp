// Persistent workers over a ring of jobs. The per-item cost is one relaxed fetch_add per chunk;
// the mutex is taken only to find the next job and to signal completion.
#include <ig_core/RenderPool.h>

#include <algorithm>

namespace fieldcast::core {

RenderPool::RenderPool(int threads) {
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  mWorkers.reserve(static_cast<std::size_t>(threads));
  for (int w = 0; w < threads; ++w) mWorkers.emplace_back([this, w] { workerLoop(w); });
}

RenderPool::~RenderPool() {
  {
    std::lock_guard lock(mMutex);
    mStop = true;
  }
  mWork.notify_all();
  for (std::thread& t : mWorkers) t.join();
}

void RenderPool::submit(PoolJob& job) {
  job.next.store(0, std::memory_order_relaxed);
  job.done.store(0, std::memory_order_relaxed);
  job.chunk = std::max(job.chunk, 1);
  job.users = 0;
  {
    std::unique_lock lock(mMutex);
    job.complete = job.count <= 0;
    if (job.complete) return;
    mDone.wait(lock, [this] { return mCount < kMaxQueued; });
    mQueue[(mHead + mCount) % kMaxQueued] = &job;
    ++mCount;
  }
  mWork.notify_all();
}

void RenderPool::wait(PoolJob& job) {
  std::unique_lock lock(mMutex);
  mDone.wait(lock, [&job] { return job.complete; });
}

void RenderPool::workerLoop(int worker) noexcept {
  std::unique_lock lock(mMutex);
  for (;;) {
    // Drop jobs whose items are all taken (their last chunks may still be running elsewhere).
    while (mCount > 0 && mQueue[mHead]->next.load(std::memory_order_relaxed) >= mQueue[mHead]->count) {
      mHead = (mHead + 1) % kMaxQueued;
      --mCount;
      mDone.notify_all();
    }
    if (mCount == 0) {
      if (mStop) return;
      mWork.wait(lock);
      continue;
    }
    PoolJob* job = mQueue[mHead];
    ++job->users;
    lock.unlock();
    // Take chunks until this job runs dry, then look for the next one (no barrier between frames).
    for (;;) {
      const int begin = job->next.fetch_add(job->chunk, std::memory_order_relaxed);
      if (begin >= job->count) break;
      const int end = std::min(begin + job->chunk, job->count);
      job->run(job->context, begin, end, worker);
      job->done.fetch_add(end - begin, std::memory_order_acq_rel);
    }
    lock.lock();
    // The job is complete when its last user leaves: every taken chunk has then finished, and the
    // job has left the queue (it is exhausted), so nothing touches it after `complete` is set.
    if (--job->users == 0 && job->done.load(std::memory_order_acquire) == job->count) {
      if (mCount > 0 && mQueue[mHead] == job) {
        mHead = (mHead + 1) % kMaxQueued;
        --mCount;
      }
      job->complete = true;
      mDone.notify_all();
    }
  }
}

}  // namespace fieldcast::core
