#pragma once
// The input thread for the control stick: opens the device through a factory, maps its frames
// with a StickMapper and publishes the newest ControlState in a SeqLock — the field thread only
// ever does a lock-free load (controlsAt), so nothing in the input path can stall it. When the
// device disappears the last state is held and decays to neutral over the profile's time, the
// loss is logged once, and the device is reopened with exponential backoff. Any source can be
// recorded to a file on the way through.

#include <io_bridge/ControlState.h>
#include <io_bridge/InputRecording.h>
#include <io_bridge/InputSource.h>
#include <io_bridge/StickMapper.h>
#include <io_bridge/StickProfile.h>

#include <fieldcast/SeqLock.h>
#include <fieldcast/Time.h>

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

namespace fieldcast::io {

/// Exponential backoff between reconnection attempts: min, 2·min, 4·min … capped at max.
class Backoff {
 public:
  Backoff(Nanoseconds min, Nanoseconds max) noexcept : mMin(min), mMax(max), mNext(min) {}
  /// The delay before the next attempt; doubles the one after. RT-safe.
  Nanoseconds next() noexcept {
    const Nanoseconds d = mNext;
    mNext = std::min(mMax, mNext * 2);
    return d;
  }
  /// Back to the minimum (after a success). RT-safe.
  void reset() noexcept { mNext = mMin; }

 private:
  Nanoseconds mMin, mMax, mNext;
};

/// Tells the reconnect wait that the device may be back (a USB hotplug arrival), so it is
/// reopened at once rather than at the next backoff poll. Owned by the input thread.
class DeviceArrivalWatch {
 public:
  virtual ~DeviceArrivalWatch() = default;
  /// Waits up to `timeout` for an arrival; true when one came.
  virtual bool waitForArrival(Nanoseconds timeout) = 0;
};

/// Options of the stick input thread.
struct StickInputOptions {
  Nanoseconds readTimeout{std::chrono::milliseconds(20)};  ///< longest block in one read (stop latency)
  Nanoseconds backoffMin{std::chrono::milliseconds(100)};  ///< first reconnection delay
  Nanoseconds backoffMax{std::chrono::seconds(5)};         ///< longest reconnection delay
  std::filesystem::path recordPath;                        ///< record every event here; empty: no recording
  bool reconnect = true;  ///< false: finish when the source ends or is lost (replays, pipes)
  /// Reopen on arrival (libusb hotplug) while waiting; the backoff poll stays as the fallback. May be null.
  std::shared_ptr<DeviceArrivalWatch> arrivals;
};

/// Figures of the input thread (read from any thread).
struct StickInputStats {
  std::uint64_t frames = 0;
  std::uint64_t connects = 0;
  std::uint64_t losses = 0;
  std::uint64_t failedOpens = 0;
  std::uint64_t rejectedReports = 0;
  std::uint64_t droppedBursts = 0;
  std::uint64_t arrivals = 0;  ///< reopen attempts brought forward by a hotplug arrival
};

/// The held state decayed toward neutral at time `t` (see StickInput). RT-safe.
ControlState decayToward(const ControlState& held, TimePoint t, const StickProfile& profile) noexcept;

/// The stick input thread and its lock-free hand-off.
class StickInput {
 public:
  /// Opens a source; throws std::exception (with the reason) when the device is not there.
  using SourceFactory = std::function<std::unique_ptr<InputSource>()>;

  StickInput(SourceFactory factory, StickProfile profile, StickInputOptions options, Clock& clock);
  ~StickInput();
  StickInput(const StickInput&) = delete;
  StickInput& operator=(const StickInput&) = delete;

  /// Starts the input thread (which loops step()). Not RT-safe.
  void start();
  /// Stops and joins the thread; returns within about one readTimeout. Not RT-safe.
  void stop();

  /// One iteration of the input thread: open the device when due, else read and publish.
  /// Returns false once finished (source ended and reconnect is off). Tests call it directly.
  bool step();

  /// The controls to apply at `t`: the newest state, or while the device is lost the held state
  /// decayed toward neutral. Any thread; lock-free, never waits for the input thread. RT-safe.
  ControlState controlsAt(TimePoint t) const noexcept { return decayToward(mPublished.load(), t, mProfile); }
  /// The profile it maps with (its [buttons] cockpit actions, for the service).
  const StickProfile& profile() const noexcept { return mProfile; }
  /// The newest published state, undecayed. RT-safe.
  ControlState latest() const noexcept { return mPublished.load(); }
  /// Counters. Any thread.
  StickInputStats stats() const noexcept;

 private:
  void lose(TimePoint now, const char* why);

  SourceFactory mFactory;
  StickProfile mProfile;
  StickInputOptions mOptions;
  Clock& mClock;
  Backoff mBackoff;
  TimePoint mNextAttempt{};
  bool mFinished = false;
  bool mFailureLogged = false;
  std::unique_ptr<InputSource> mSource;
  std::optional<StickMapper> mMapper;
  std::unique_ptr<InputRecorder> mRecorder;
  std::vector<InputEvent> mEvents;
  ControlState mHeld;
  SeqLock<ControlState> mPublished;
  std::atomic<std::uint64_t> mFrames{0}, mConnects{0}, mLosses{0}, mFailedOpens{0};
  std::atomic<std::uint64_t> mRejected{0}, mDropped{0}, mArrivals{0};
  std::uint64_t mRejectedBefore = 0, mDroppedBefore = 0;  // totals of earlier connections
  std::atomic<bool> mRunning{false};
  std::thread mThread;
};

}  // namespace fieldcast::io
