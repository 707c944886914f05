// SinkHub: one single-producer/single-consumer ring of preallocated fields per sink. The field
// thread owns `head`, the sink's worker owns `tail`; a slot is the producer's again only once the
// worker has advanced `tail` past it, so no field is ever overwritten while a sink reads it.

#include <io_bridge/SinkHub.h>

#include <spdlog/spdlog.h>

#include <pthread.h>
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <csignal>
#include <mutex>
#include <semaphore>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace fieldcast::io {

namespace {

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

struct SinkHub::Lane {
  std::unique_ptr<FieldSink> sink;
  std::string name;
  std::vector<Field> slots;                        // preallocated to the largest field
  alignas(64) std::atomic<std::uint64_t> head{0};  // next slot the field thread fills
  alignas(64) std::atomic<std::uint64_t> tail{0};  // next slot the worker consumes
  std::counting_semaphore<(1 << 30)> wake{0};
  std::atomic<bool> stopRequested{false};
  std::atomic<bool> ended{false};

  // Figures: written by one thread each, read by anyone.
  std::atomic<std::uint64_t> published{0}, droppedFull{0}, rejected{0};
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

  std::uint64_t reportedDrops = 0;
  TimePoint lastDropReport{};
  const auto depth = static_cast<std::uint64_t>(slots.size());
  for (;;) {
    wake.acquire();
    std::uint64_t t = tail.load(std::memory_order_relaxed);
    while (t != head.load(std::memory_order_acquire)) {
      const Field& field = slots[t % depth];
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

void SinkHub::add(std::unique_ptr<FieldSink> sink) {
  if (mRunning) throw std::logic_error("SinkHub::add: sinks must be added before start()");
  if (!sink) throw std::invalid_argument("SinkHub::add: null sink");
  auto lane = std::make_unique<Lane>();
  lane->name = sink->name();
  lane->sink = std::move(sink);
  lane->slots.resize(static_cast<std::size_t>(mOptions.queueDepth));
  const FieldParity largest = mFormat.scan == ScanMode::Progressive ? FieldParity::Progressive : FieldParity::Top;
  for (Field& slot : lane->slots) {
    // Full-size images now, so that publish() copies into capacity that is already there.
    slot.image = Image(mFormat.widthPx, mFormat.fieldRows(largest), mFormat.pixelFormat);
  }
  mLanes.push_back(std::move(lane));
}

void SinkHub::start() {
  if (mRunning) return;
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
  const bool fits = mFormat.accepts(field);
  for (auto& lanePtr : mLanes) {
    Lane& lane = *lanePtr;
    if (lane.ended.load(std::memory_order_relaxed)) continue;
    lane.published.fetch_add(1, std::memory_order_relaxed);
    if (!fits) {
      lane.rejected.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    const std::uint64_t h = lane.head.load(std::memory_order_relaxed);
    if (h - lane.tail.load(std::memory_order_acquire) >= lane.slots.size()) {
      lane.droppedFull.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    // Copy-assignment reuses the slot's preallocated image (same or smaller size): no allocation.
    lane.slots[h % lane.slots.size()] = field;
    lane.head.store(h + 1, std::memory_order_release);
    lane.wake.release();
  }
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
    f.consumed = lane->consumed.load(std::memory_order_relaxed);
    f.droppedFull = lane->droppedFull.load(std::memory_order_relaxed);
    f.rejected = lane->rejected.load(std::memory_order_relaxed);
    f.maxConsumeNs = lane->maxConsumeNs.load(std::memory_order_relaxed);
    f.totalConsumeNs = lane->totalConsumeNs.load(std::memory_order_relaxed);
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
    s << f.name << ": " << f.consumed << " fields, " << f.droppedFull << " dropped (queue full), " << f.rejected
      << " rejected, mean " << meanMs << " ms, max " << static_cast<double>(f.maxConsumeNs) * 1e-6 << " ms";
    if (f.ended) s << ", ENDED: " << f.endReason;
    s << '\n';
  }
  return s.str();
}

}  // namespace fieldcast::io
