#include <io_bridge/GpioInput.h>

#include <spdlog/spdlog.h>

#include <poll.h>

#include <cerrno>

namespace fieldcast::io {

GpioInputs::GpioInputs(Nanoseconds debounce, RationalRate nominalSyncRate)
    : mDebounce(debounce), mSync(nominalSyncRate) {
  mSyncOut.store(mSync.estimate());
  mDiscretes.store(mState);
}

GpioInputs::~GpioInputs() { stop(); }

void GpioInputs::addDiscrete(Discrete which, std::unique_ptr<GpioEdgeLine> line) {
  const auto i = static_cast<std::size_t>(which);
  mState.level[i] = line->level();
  mDiscretes.store(mState);
  mLines.push_back(Line{std::move(line), static_cast<int>(i), true});
}

void GpioInputs::addSync(std::unique_ptr<GpioEdgeLine> line) { mLines.push_back(Line{std::move(line), -1, true}); }

void GpioInputs::start() {
  if (mRunning.exchange(true)) return;
  mThread = std::thread([this] {
    try {
      while (mRunning.load(std::memory_order_relaxed) && pump(std::chrono::milliseconds(50))) {
      }
    } catch (const std::exception& e) {
      spdlog::error("GPIO input thread stopped: {}", e.what());
    }
  });
}

void GpioInputs::stop() {
  mRunning.store(false);
  if (mThread.joinable()) mThread.join();
}

void GpioInputs::handle(const Line& line, const GpioEdge& edge) {
  if (line.role < 0) {
    if (edge.kind == GpioEdgeKind::Rising) {
      mSync.onPulse(edge.time);
      mSyncOut.store(mSync.estimate());
    }
    return;
  }
  const auto i = static_cast<std::size_t>(line.role);
  const std::int64_t t = edge.time.time_since_epoch().count();
  const bool rising = edge.kind == GpioEdgeKind::Rising;
  // Debounce: a contact bounces for a few milliseconds; the first edge of a burst is the truth.
  if (mState.lastEdgeNs[i] != 0 && t - mState.lastEdgeNs[i] < mDebounce.count()) {
    ++mState.bounces;
    return;
  }
  if (rising == mState.level[i]) return;  // no change of level (a lost opposite edge)
  mState.level[i] = rising;
  mState.lastEdgeNs[i] = t;
  if (rising) ++mState.presses[i];
}

bool GpioInputs::pump(Nanoseconds timeout) {
  std::vector<pollfd> fds;
  std::vector<std::size_t> which;
  for (std::size_t i = 0; i < mLines.size(); ++i) {
    if (!mLines[i].alive) continue;
    fds.push_back(pollfd{mLines[i].line->eventFd(), POLLIN, 0});
    which.push_back(i);
  }
  if (fds.empty()) return false;
  const auto ms = static_cast<int>(std::max<std::int64_t>(0, (timeout.count() + 999'999) / 1'000'000));
  const int ready = ::poll(fds.data(), fds.size(), ms);
  if (ready <= 0) return true;
  bool changed = false;
  for (std::size_t j = 0; j < fds.size(); ++j) {
    if (fds[j].revents == 0) continue;
    Line& line = mLines[which[j]];
    mEdges.clear();
    if (!line.line->readEdges(mEdges)) {
      line.alive = false;  // logged once; GPIO chips do not come back by themselves
      spdlog::error("GPIO line {} is gone; its input is no longer read", line.line->name());
      continue;
    }
    for (const GpioEdge& e : mEdges) handle(line, e);
    changed = changed || (line.role >= 0 && !mEdges.empty());
  }
  if (changed) mDiscretes.store(mState);
  return true;
}

}  // namespace fieldcast::io
