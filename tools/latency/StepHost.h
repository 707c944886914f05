#pragma once
// A host for the running service: a CIGI 3.3 host on 127.0.0.1 that holds the ownship still at one
// pose and sends a host frame (IG Control, the ownship's Entity Control and a zero Rate Control)
// every 1/60 s. turnTo() steps the ownship's heading; it returns when the first datagram with the
// new heading left, on CLOCK_MONOTONIC — the instant a host → field latency is measured from.

#include "FirstSend.h"

#include <io_bridge/cigi/MessageBuilder.h>

#include <arpa/inet.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <thread>

namespace fieldcast::tools {

/// Where the host holds the ownship: geodetic, as Entity Control carries it.
struct HeldOwnship {
  double latitudeDeg = 0, longitudeDeg = 0, altitudeM = 0;
  double yawDeg = 0, pitchDeg = 0;
};

class StepHost {
 public:
  /// Starts sending to the IG at 127.0.0.1:`igPort`.
  StepHost(std::uint16_t igPort, const HeldOwnship& ownship) : mOwnship(ownship) {
    mFd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    mIg.sin_family = AF_INET;
    mIg.sin_port = htons(igPort);
    mIg.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (mFd >= 0) mThread = std::thread([this] { serve(); });
  }
  ~StepHost() {
    mStop = true;
    if (mThread.joinable()) mThread.join();
    if (mFd >= 0) ::close(mFd);
  }
  StepHost(const StepHost&) = delete;
  StepHost& operator=(const StepHost&) = delete;

  bool open() const noexcept { return mFd >= 0; }

  /// Holds the heading at the start's plus `offsetDeg` from the next host frame on; returns the
  /// CLOCK_MONOTONIC instant (ns) that frame's datagram was sent, or 0 when none left within a second.
  std::int64_t turnTo(double offsetDeg) {
    return mSends.waitFor(mSends.change([&] { mYawOffsetDeg = offsetDeg; }));
  }

 private:
  void serve() {
    using Clock = std::chrono::steady_clock;
    constexpr auto kHostPeriod = std::chrono::microseconds(16'667);  // 60 Hz
    io::cigi::HostMessageBuilder message;
    const Clock::time_point start = Clock::now();
    for (std::uint32_t frame = 0; !mStop; ++frame) {
      std::this_thread::sleep_until(start + frame * kHostPeriod);
      double offsetDeg = 0.0;
      const std::uint64_t generation = mSends.current([&] { offsetDeg = mYawOffsetDeg; });
      io::cigi::IgControl control;
      control.extrapolationEnabled = true;
      control.hostFrameNumber = frame;
      control.timestampValid = true;
      control.timestampTicks = static_cast<std::uint32_t>(std::llround(frame / 60.0 / 10e-6));
      message.start(control);
      io::cigi::EntityControl ownship;
      ownship.entityId = 0;
      ownship.latitudeDegOrXM = mOwnship.latitudeDeg;
      ownship.longitudeDegOrYM = mOwnship.longitudeDeg;
      ownship.altitudeMOrZM = mOwnship.altitudeM;
      ownship.yawDeg = static_cast<float>(mOwnship.yawDeg + offsetDeg);
      ownship.pitchDeg = static_cast<float>(mOwnship.pitchDeg);
      ownship.extrapolationEnabled = true;
      message.add(ownship);
      message.add(io::cigi::RateControl{});  // entity 0, world frame, all rates zero: it stands still
      // The instant is taken just before the datagram leaves: the latency includes the whole path
      const std::int64_t now = FirstSend::monotonicNs();
      const auto bytes = message.bytes();
      if (::sendto(mFd, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&mIg), sizeof mIg) < 0) {
        continue;
      }
      mSends.sent(generation, now);
    }
  }

  HeldOwnship mOwnship;
  int mFd = -1;
  sockaddr_in mIg{};
  std::thread mThread;
  std::atomic<bool> mStop{false};
  FirstSend mSends;
  double mYawOffsetDeg = 0.0;  // guarded by mSends
};

}  // namespace fieldcast::tools
