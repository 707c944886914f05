#pragma once
// A GPIO line for tests: edges are queued by the test and signalled through a pipe, so the GPIO
// thread's poll() sees it exactly as it sees a libgpiod line's event descriptor.

#include <io_bridge/GpioInput.h>

#include <fcntl.h>
#include <unistd.h>

#include <deque>
#include <memory>
#include <mutex>

namespace fieldcast::io::testing {

class FakeGpioLine final : public GpioEdgeLine {
 public:
  struct Wire {
    std::mutex mutex;
    std::deque<GpioEdge> edges;
    bool gone = false;
    bool level = false;
    int fds[2]{-1, -1};
    Wire() { (void)::pipe2(fds, O_CLOEXEC | O_NONBLOCK); }
    ~Wire() {
      ::close(fds[0]);
      ::close(fds[1]);
    }
    void edge(std::int64_t tNs, GpioEdgeKind kind) {
      {
        std::lock_guard lock(mutex);
        edges.push_back(GpioEdge{TimePoint{Nanoseconds{tNs}}, kind});
      }
      const char b = 1;
      (void)::write(fds[1], &b, 1);
    }
    void unplug() {
      {
        std::lock_guard lock(mutex);
        gone = true;
      }
      const char b = 1;
      (void)::write(fds[1], &b, 1);
    }
  };

  explicit FakeGpioLine(std::shared_ptr<Wire> wire) : mWire(std::move(wire)) {}
  std::string name() const override { return "fake:0"; }
  int eventFd() const override { return mWire->fds[0]; }
  bool readEdges(std::vector<GpioEdge>& out) override {
    char buf[64];
    while (::read(mWire->fds[0], buf, sizeof buf) > 0) {
    }
    std::lock_guard lock(mWire->mutex);
    if (mWire->gone) return false;
    out.insert(out.end(), mWire->edges.begin(), mWire->edges.end());
    mWire->edges.clear();
    return true;
  }
  bool level() override { return mWire->level; }

 private:
  std::shared_ptr<Wire> mWire;
};

}  // namespace fieldcast::io::testing
