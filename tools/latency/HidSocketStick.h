#pragma once
// A stick for the running service: a HID device server on a UNIX SOCK_SEQPACKET socket (the
// service's `hidsocket:` input source connects to it) that sends its current report every 10 ms.
// set() changes the report and returns when it left, on CLOCK_MONOTONIC — the instant an
// end-to-end latency is measured from. The service may connect more than once (it opens the
// stick at start-up to describe it, then for good): the newest connection is served.

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include "FirstSend.h"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace fieldcast::tools {

class HidSocketStick {
 public:
  /// Listens at `path` and starts sending `report` to whoever connects.
  HidSocketStick(const std::string& path, std::span<const std::uint8_t> report)
      : mReport(report.begin(), report.end()) {
    mListen = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, path.c_str(), sizeof address.sun_path - 1);
    mListening = path.size() < sizeof address.sun_path &&
                 ::bind(mListen, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0 &&
                 ::listen(mListen, 2) == 0;
    if (mListening) mThread = std::thread([this] { serve(); });
  }
  ~HidSocketStick() {
    mStop = true;
    if (mThread.joinable()) mThread.join();
    ::close(mListen);
  }
  HidSocketStick(const HidSocketStick&) = delete;
  HidSocketStick& operator=(const HidSocketStick&) = delete;

  bool listening() const noexcept { return mListening; }
  bool connected() const noexcept { return mConnected.load(); }

  /// Sends `report` from the next write on; returns the CLOCK_MONOTONIC instant (ns) of that
  /// write, or 0 when nothing was written within a second (no service connected).
  std::int64_t set(std::span<const std::uint8_t> report) {
    return mSends.waitFor(mSends.change([&] { mReport.assign(report.begin(), report.end()); }));
  }

 private:
  void serve() {
    int device = -1;
    std::vector<std::uint8_t> report;
    while (!mStop) {
      pollfd p{mListen, POLLIN, 0};
      if (::poll(&p, 1, device < 0 ? 50 : 0) > 0) {
        const int next = ::accept4(mListen, nullptr, nullptr, SOCK_CLOEXEC);
        if (next >= 0) {
          if (device >= 0) ::close(device);
          device = next;
          mConnected = true;
        }
      }
      if (device < 0) continue;
      const std::uint64_t generation = mSends.current([&] { report = mReport; });
      // The instant is taken just before the report leaves: the latency includes the whole path
      const std::int64_t now = FirstSend::monotonicNs();
      if (::send(device, report.data(), report.size(), MSG_NOSIGNAL) < 0) {
        ::close(device);
        device = -1;
        continue;
      }
      mSends.sent(generation, now);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (device >= 0) ::close(device);
  }

  int mListen = -1;
  bool mListening = false;
  std::thread mThread;
  std::atomic<bool> mStop{false}, mConnected{false};
  FirstSend mSends;
  std::vector<std::uint8_t> mReport;  // guarded by mSends
};

}  // namespace fieldcast::tools
