#pragma once
// Cockpit discretes (freeze, reset, trigger) and the external sync input, read from GPIO lines
// as kernel-timestamped edges. Lines are a seam: libgpiod v1 (Debian 12's libgpiod 1.6) in the
// service, a fake line in tests. One thread polls every line's event descriptor; results are
// published lock-free (SeqLock) for the field thread.

#include <io_bridge/ExternalSync.h>

#include <fieldcast/SeqLock.h>
#include <fieldcast/Time.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace fieldcast::io {

/// Which way a line changed (logical level: active-low is already applied).
enum class GpioEdgeKind : std::uint8_t { Rising, Falling };

/// One edge with the kernel's timestamp on CLOCK_MONOTONIC.
struct GpioEdge {
  TimePoint time{};
  GpioEdgeKind kind = GpioEdgeKind::Rising;
};

/// An input line that reports edges. Owned and read by the GPIO thread.
class GpioEdgeLine {
 public:
  virtual ~GpioEdgeLine() = default;
  /// For messages: "gpiochip0:17".
  virtual std::string name() const = 0;
  /// A descriptor that polls readable while edges are queued.
  virtual int eventFd() const = 0;
  /// Appends the queued edges, oldest first. False when the line is gone.
  virtual bool readEdges(std::vector<GpioEdge>& out) = 0;
  /// The current logical level.
  virtual bool level() = 0;
};

/// Pull resistor of an input line.
enum class GpioBias : std::uint8_t { AsIs, Disable, PullUp, PullDown };

/// Which line to open and how.
struct GpioLineConfig {
  std::string chip = "gpiochip0";  ///< name, path, label or number (gpiod_chip_open_lookup)
  unsigned offset = 0;
  bool activeLow = false;  ///< a switch to ground with a pull-up reads pressed as 1
  GpioBias bias = GpioBias::AsIs;
  std::string consumer = "fieldcast";
};

/// Parses "gpiochip0:17", optionally followed by ":active_low" and one of ":pull_up", ":pull_down",
/// ":bias_off" (in any order). Throws std::runtime_error naming the text and what was expected.
GpioLineConfig parseGpioLineSpec(const std::string& spec);

/// Requests both-edge events on a line through libgpiod v1. Throws std::runtime_error naming the
/// chip, the line and the reason.
std::unique_ptr<GpioEdgeLine> openGpiodEdgeLine(const GpioLineConfig& config);
/// The GPIO chips present (/dev/gpiochip*). Not RT-safe.
std::vector<std::string> listGpioChips();

/// The discrete inputs of a cockpit.
enum class Discrete : std::uint8_t { Freeze, Reset, Trigger };
/// Number of discrete inputs.
constexpr std::size_t kDiscretes = 3;

/// What the discretes say. Presses count up forever, so a reader that compares two snapshots
/// never misses a press between its reads.
struct DiscreteSnapshot {
  std::array<bool, kDiscretes> level{};               ///< debounced logical level
  std::array<std::uint32_t, kDiscretes> presses{};    ///< rising edges accepted so far
  std::array<std::int64_t, kDiscretes> lastEdgeNs{};  ///< kernel time of the last accepted edge
  std::uint32_t bounces = 0;                          ///< edges rejected by the debounce

  bool isOn(Discrete d) const noexcept { return level[static_cast<std::size_t>(d)]; }
  std::uint32_t pressCount(Discrete d) const noexcept { return presses[static_cast<std::size_t>(d)]; }
};

/// The GPIO input thread.
class GpioInputs {
 public:
  /// `debounce`: edges closer than this to the last accepted edge of the same line are bounces.
  GpioInputs(Nanoseconds debounce, RationalRate nominalSyncRate);
  ~GpioInputs();
  GpioInputs(const GpioInputs&) = delete;
  GpioInputs& operator=(const GpioInputs&) = delete;

  /// Adds a discrete line; its initial level is read now. Before start() only.
  void addDiscrete(Discrete which, std::unique_ptr<GpioEdgeLine> line);
  /// Adds the external sync line (rising edges are sync pulses). Before start() only.
  void addSync(std::unique_ptr<GpioEdgeLine> line);

  void start();
  void stop();
  /// One poll over all lines, waiting up to `timeout`. False when no line is left. Tests call it.
  bool pump(Nanoseconds timeout);

  /// The discretes now. Any thread; lock-free. RT-safe.
  DiscreteSnapshot discretes() const noexcept { return mDiscretes.load(); }
  /// The external sync estimate now. Any thread; lock-free. RT-safe.
  SyncEstimate sync() const noexcept { return mSyncOut.load(); }

 private:
  struct Line {
    std::unique_ptr<GpioEdgeLine> line;
    int role = -1;  // Discrete index, or -1 for sync
    bool alive = true;
  };
  void handle(const Line& line, const GpioEdge& edge);

  Nanoseconds mDebounce;
  std::vector<Line> mLines;
  std::vector<GpioEdge> mEdges;
  DiscreteSnapshot mState;
  ExternalSyncEstimator mSync;
  SeqLock<DiscreteSnapshot> mDiscretes;
  SeqLock<SyncEstimate> mSyncOut;
  std::atomic<bool> mRunning{false};
  std::thread mThread;
};

}  // namespace fieldcast::io
