// SinkHub: one pool of preallocated fields shared by all sinks, and per sink a single-producer/
// single-consumer ring of slot indices. publish() copies the field once into a free pool slot,
// sets the slot's reference count to the number of sinks that take it, and pushes its index to
// each of them; each worker drops its reference when done. A slot is reused only at count zero
// (acquire, paired with the workers' release), so no field is overwritten while a sink reads it.
// The pool has depth × sinks + 1 slots: even with every ring full there is always a free slot.

#include <io_bridge/SinkHub.h>

#include <spdlog/spdlog.h>

#include <pthread.h>
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <csignal>
#include <cstring>
#include <mutex>
#include <semaphore>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace fieldcast::io {

namespace {

constexpr std::uint64_t kNoSchedule = ~std::uint64_t{0};

std::uint64_t elapsedNs(TimePoint from, TimePoint to) noexcept {
  return static_cast<std::uint64_t>(std::max<std::int64_t>(0, (to - from).count()));
}

// Writes to a closed pipe raise SIGPIPE in the thread that wrote. Blocking it here turns a dead
// consumer into an EPIPE error the sink reports, instead of the signal ending the whole service.
void blockSigpipeInThisThread() noexcept {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

}  // namespace

struct SinkHub::Pool {
  std::vector<Field> fields;                 // preallocated to the largest field
  std::vector<std::atomic<int>> references;  // sinks still to finish with each field
  std::size_t next = 0;                      // where the search for a free slot starts
};

struct SinkHub::Lane {
  std::unique_ptr<FieldSink> sink;
  std::string name;
  Pool* pool = nullptr;
  SinkWorkerOptions workerOptions;
  std::atomic<bool> realtime{false};
  std::vector<std::uint32_t> ring;                 // pool slot indices, queueDepth of them
  alignas(64) std::atomic<std::uint64_t> head{0};  // next slot the field thread fills
  alignas(64) std::atomic<std::uint64_t> tail{0};  // next slot the worker consumes
  std::counting_semaphore<(1 << 30)> wake{0};
  std::atomic<bool> stopRequested{false};
  std::atomic<std::uint64_t> scheduleStart{kNoSchedule};  // beginSchedule()'s field, if it came
  std::atomic<std::uint64_t> scheduleEnd{kNoSchedule};    // endSchedule()'s field, if it came
  std::atomic<bool> ended{false};

  // Figures: written by one thread each, read by anyone.
  std::atomic<std::uint64_t> published{0}, passedOver{0}, droppedFull{0}, rejected{0};
  std::atomic<std::uint64_t> consumed{0}, maxConsumeNs{0}, totalConsumeNs{0};
  mutable std::mutex reasonMutex;
  std::string endReason;

  // Start-up hand-shake.
  std::mutex openMutex;
  std::condition_variable openDone;
  bool opened = false;
  std::string openError;

  std::thread worker;

  void run(const StreamFormat& format);
  void endWith(const std::string& reason);
  void drainWithoutConsuming();
};

void SinkHub::Lane::endWith(const std::string& reason) {
  {
    std::lock_guard lock(reasonMutex);
    endReason = reason;
  }
  ended.store(true, std::memory_order_release);
  spdlog::error("sink '{}' ended: {}; the service continues without it", name, reason);
  try {
    sink->close();
  } catch (const std::exception& e) {
    spdlog::warn("sink '{}': close after end failed: {}", name, e.what());
  }
}

void SinkHub::Lane::run(const StreamFormat& format) {
  blockSigpipeInThisThread();
  if (workerOptions.realtimePriority > 0) {
    sched_param param{};
    param.sched_priority = workerOptions.realtimePriority;
    const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    if (rc == 0) {
      realtime.store(true, std::memory_order_relaxed);
    } else {
      spdlog::warn(
          "sink '{}': real-time priority {} refused ({}); it runs at normal priority (grant CAP_SYS_NICE "
          "or an rtprio limit for tighter timing)",
          name, workerOptions.realtimePriority, std::strerror(rc));
    }
  }
  try {
    sink->open(format);
  } catch (const std::exception& e) {
    std::lock_guard lock(openMutex);
    openError = e.what();
    opened = true;
    openDone.notify_all();
    return;
  }
  {
    std::lock_guard lock(openMutex);
    opened = true;
  }
  openDone.notify_all();

  bool started = false;  // scheduleStarted() asked for, before the first field
  std::uint64_t reportedDrops = 0;
  TimePoint lastDropReport{};
  const auto depth = static_cast<std::uint64_t>(ring.size());
  for (;;) {
    wake.acquire();
    std::uint64_t t = tail.load(std::memory_order_relaxed);
    while (t != head.load(std::memory_order_acquire)) {
      const std::uint32_t slot = ring[t % depth];
      const Field& field = pool->fields[slot];
      if (!started && !ended.load(std::memory_order_relaxed)) {
        started = true;
        // Stored before the first field was published (whose head this worker has acquired).
        const std::uint64_t first = scheduleStart.load(std::memory_order_acquire);
        try {
          if (first != kNoSchedule) sink->scheduleStarted(first);
        } catch (const std::exception& e) {
          spdlog::error("sink '{}': starting the schedule failed: {}", name, e.what());
        }
      }
      if (!ended.load(std::memory_order_relaxed)) {
        const TimePoint begin = MonotonicClock::now();
        SinkStatus status = SinkStatus::Ended;
        std::string failure;
        try {
          status = sink->consume(field);
        } catch (const std::exception& e) {
          failure = e.what();
        }
        const std::uint64_t ns = elapsedNs(begin, MonotonicClock::now());
        totalConsumeNs.fetch_add(ns, std::memory_order_relaxed);
        if (ns > maxConsumeNs.load(std::memory_order_relaxed)) maxConsumeNs.store(ns, std::memory_order_relaxed);
        consumed.fetch_add(1, std::memory_order_relaxed);
        if (status == SinkStatus::Ended) endWith(failure.empty() ? sink->endReason() : failure);
      }
      pool->references[slot].fetch_sub(1, std::memory_order_release);  // the field may be reused
      tail.store(++t, std::memory_order_release);
    }
    // Report queue-full drops from here, never from the field thread; at most once a second.
    const std::uint64_t drops = droppedFull.load(std::memory_order_relaxed);
    const TimePoint now = MonotonicClock::now();
    if (drops != reportedDrops && now - lastDropReport >= std::chrono::seconds(1)) {
      spdlog::warn("sink '{}': {} fields dropped (queue full) since the last report, {} in all", name,
                   drops - reportedDrops, drops);
      reportedDrops = drops;
      lastDropReport = now;
    }
    if (stopRequested.load(std::memory_order_acquire) && t == head.load(std::memory_order_acquire)) break;
  }
  if (!ended.load(std::memory_order_relaxed)) {
    const std::uint64_t end = scheduleEnd.load(std::memory_order_acquire);
    try {
      if (end != kNoSchedule) sink->scheduleEnded(end);
    } catch (const std::exception& e) {
      spdlog::error("sink '{}': completing the schedule failed: {}", name, e.what());
    }
    try {
      sink->close();
    } catch (const std::exception& e) {
      spdlog::error("sink '{}': close failed: {}", name, e.what());
    }
  }
}

SinkHub::SinkHub(StreamFormat format, SinkHubOptions options) : mFormat(format), mOptions(options) {
  mFormat.validate();
  if (mOptions.queueDepth < 1 || mOptions.queueDepth > 64) {
    throw std::invalid_argument("SinkHub: queue depth must be 1..64, got " + std::to_string(mOptions.queueDepth));
  }
}

SinkHub::~SinkHub() { stop(); }

void SinkHub::add(std::unique_ptr<FieldSink> sink, SinkWorkerOptions worker) {
  if (mRunning) throw std::logic_error("SinkHub::add: sinks must be added before start()");
  if (!sink) throw std::invalid_argument("SinkHub::add: null sink");
  auto lane = std::make_unique<Lane>();
  lane->name = sink->name();
  lane->sink = std::move(sink);
  lane->ring.assign(static_cast<std::size_t>(mOptions.queueDepth), 0);
  if (worker.realtimePriority < 0 || worker.realtimePriority > 99) {
    throw std::invalid_argument("SinkHub::add: real-time priority must be 0..99, got " +
                                std::to_string(worker.realtimePriority));
  }
  lane->workerOptions = worker;
  mLanes.push_back(std::move(lane));
}

void SinkHub::allocatePool() {
  // Every ring full still leaves one slot free for the next publish().
  const std::size_t slots = static_cast<std::size_t>(mOptions.queueDepth) * mLanes.size() + 1;
  mPool = std::make_unique<Pool>();
  mPool->fields.resize(slots);
  mPool->references = std::vector<std::atomic<int>>(slots);
  const FieldParity largest = mFormat.scan == ScanMode::Progressive ? FieldParity::Progressive : FieldParity::Top;
  for (Field& field : mPool->fields) {
    // Full-size images now, so that publish() copies into capacity that is already there.
    field.image = Image(mFormat.widthPx, mFormat.fieldRows(largest), mFormat.pixelFormat);
  }
  for (auto& lane : mLanes) lane->pool = mPool.get();
}

void SinkHub::start() {
  if (mRunning) return;
  allocatePool();
  mTakes.assign(mLanes.size(), 0);
  for (auto& lane : mLanes) {
    Lane* l = lane.get();
    l->worker = std::thread([l, this] { l->run(mFormat); });
  }
  mRunning = true;
  std::string failures;
  for (auto& lane : mLanes) {
    std::unique_lock lock(lane->openMutex);
    lane->openDone.wait(lock, [&] { return lane->opened; });
    if (!lane->openError.empty()) failures += "\n  sink '" + lane->name + "': " + lane->openError;
  }
  if (!failures.empty()) {
    stop();
    throw std::runtime_error("could not open the field outputs:" + failures);
  }
}

void SinkHub::publish(const Field& field) noexcept {
  if (!mPool) return;
  const bool fits = mFormat.accepts(field);
  // Which sinks take this field: live, matching, wanting it, with room in their ring
  std::uint32_t takers = 0;
  for (std::size_t i = 0; i < mLanes.size(); ++i) {
    Lane& lane = *mLanes[i];
    mTakes[i] = 0;
    if (lane.ended.load(std::memory_order_relaxed)) continue;
    lane.published.fetch_add(1, std::memory_order_relaxed);
    if (!fits) {
      lane.rejected.fetch_add(1, std::memory_order_relaxed);
    } else if (!lane.sink->wants(field)) {
      lane.passedOver.fetch_add(1, std::memory_order_relaxed);
    } else if (lane.head.load(std::memory_order_relaxed) - lane.tail.load(std::memory_order_acquire) >=
               lane.ring.size()) {
      lane.droppedFull.fetch_add(1, std::memory_order_relaxed);
    } else {
      mTakes[i] = 1;
      ++takers;
    }
  }
  if (takers == 0) return;
  // A free slot: no sink holds it any more (acquire pairs with the workers' release)
  Pool& pool = *mPool;
  const std::size_t n = pool.fields.size();
  std::size_t slot = pool.next;
  while (pool.references[slot].load(std::memory_order_acquire) != 0) slot = (slot + 1) % n;  // one always is
  pool.next = (slot + 1) % n;
  // Copy-assignment reuses the slot's preallocated image (same or smaller size): no allocation.
  pool.fields[slot] = field;
  pool.references[slot].store(static_cast<int>(takers), std::memory_order_relaxed);
  for (std::size_t i = 0; i < mLanes.size(); ++i) {
    if (!mTakes[i]) continue;
    Lane& lane = *mLanes[i];
    const std::uint64_t h = lane.head.load(std::memory_order_relaxed);
    lane.ring[h % lane.ring.size()] = static_cast<std::uint32_t>(slot);
    lane.head.store(h + 1, std::memory_order_release);  // publishes the field and its count
    lane.wake.release();
  }
}

void SinkHub::beginSchedule(std::uint64_t firstField) noexcept {
  for (auto& lane : mLanes) lane->scheduleStart.store(firstField, std::memory_order_release);
}

void SinkHub::endSchedule(std::uint64_t firstFieldAfter) noexcept {
  for (auto& lane : mLanes) lane->scheduleEnd.store(firstFieldAfter, std::memory_order_release);
}

void SinkHub::stop() {
  if (!mRunning) return;
  for (auto& lane : mLanes) {
    lane->stopRequested.store(true, std::memory_order_release);
    lane->wake.release();
  }
  for (auto& lane : mLanes) {
    if (lane->worker.joinable()) lane->worker.join();
  }
  mRunning = false;
}

std::vector<SinkFigures> SinkHub::figures() const {
  std::vector<SinkFigures> out;
  for (const auto& lane : mLanes) {
    SinkFigures f;
    f.name = lane->name;
    f.published = lane->published.load(std::memory_order_relaxed);
    f.passedOver = lane->passedOver.load(std::memory_order_relaxed);
    f.consumed = lane->consumed.load(std::memory_order_relaxed);
    f.droppedFull = lane->droppedFull.load(std::memory_order_relaxed);
    f.rejected = lane->rejected.load(std::memory_order_relaxed);
    f.maxConsumeNs = lane->maxConsumeNs.load(std::memory_order_relaxed);
    f.totalConsumeNs = lane->totalConsumeNs.load(std::memory_order_relaxed);
    f.realtime = lane->realtime.load(std::memory_order_relaxed);
    f.ended = lane->ended.load(std::memory_order_acquire);
    if (f.ended) {
      std::lock_guard lock(lane->reasonMutex);
      f.endReason = lane->endReason;
    }
    out.push_back(std::move(f));
  }
  return out;
}

std::uint64_t SinkHub::droppedTotal() const noexcept {
  std::uint64_t total = 0;
  for (const auto& lane : mLanes) {
    total += lane->droppedFull.load(std::memory_order_relaxed) + lane->rejected.load(std::memory_order_relaxed);
  }
  return total;
}

std::string SinkHub::summary() const {
  std::ostringstream s;
  for (const SinkFigures& f : figures()) {
    const double meanMs =
        f.consumed ? static_cast<double>(f.totalConsumeNs) / static_cast<double>(f.consumed) * 1e-6 : 0.0;
    s << f.name << ": " << f.consumed << " fields, ";
    if (f.passedOver != 0) s << f.passedOver << " passed over, ";
    s << f.droppedFull << " dropped (queue full), " << f.rejected << " rejected, mean " << meanMs << " ms, max "
      << static_cast<double>(f.maxConsumeNs) * 1e-6 << " ms";
    if (f.ended) s << ", ENDED: " << f.endReason;
    s << '\n';
  }
  return s.str();
}

}  // namespace fieldcast::io
