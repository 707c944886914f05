#pragma once
// A host for the running service: a CIGI 3.3 host on 127.0.0.1 that holds the ownship still at one
// pose and sends a host frame (IG Control, the ownship's Entity Control and a zero Rate Control)
// every 1/60 s. turnTo() steps the ownship's heading; it returns when the first datagram with the
// new heading left, on CLOCK_MONOTONIC — the instant a host → field latency is measured from.

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
    std::uint64_t generation = 0;
    {
      const std::lock_guard lock(mMutex);
      mYawOffsetDeg = offsetDeg;
      generation = ++mGeneration;
    }
    for (int i = 0; i < 1000; ++i) {
      {
        const std::lock_guard lock(mMutex);
        if (mSentGeneration == generation) return mSentNs;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return 0;
  }

  static std::int64_t monotonicNs() noexcept {
    timespec ts{};
    ::clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
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
      std::uint64_t generation = 0;
      {
        const std::lock_guard lock(mMutex);
        offsetDeg = mYawOffsetDeg;
        generation = mGeneration;
      }
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
      const std::int64_t now = monotonicNs();
      const auto bytes = message.bytes();
      if (::sendto(mFd, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&mIg), sizeof mIg) < 0) {
        continue;
      }
      const std::lock_guard lock(mMutex);
      if (mSentGeneration != generation) {  // the first frame with this heading
        mSentGeneration = generation;
        mSentNs = now;
      }
    }
  }

  HeldOwnship mOwnship;
  int mFd = -1;
  sockaddr_in mIg{};
  std::thread mThread;
  std::atomic<bool> mStop{false};
  std::mutex mMutex;
  double mYawOffsetDeg = 0.0;         // guarded by mMutex, as are:
  std::uint64_t mGeneration = 0;      // turnTo() calls so far
  std::uint64_t mSentGeneration = 0;  // the newest heading sent ...
  std::int64_t mSentNs = 0;           // ... first sent at this instant
};

}  // namespace fieldcast::tools
