#pragma once
// The interface every input device (and a replayed recording) offers the input thread.

#include <io_bridge/InputEvent.h>

#include <fieldcast/Time.h>

#include <cstdint>
#include <vector>

namespace fieldcast::io {

/// What one read() produced.
enum class ReadResult : std::uint8_t {
  Events,   ///< one or more complete frames were appended
  Timeout,  ///< nothing arrived within the timeout
  Lost,     ///< the device went away (unplugged, ENODEV); the source is finished
  End,      ///< the stream ended (a pipe closed, a replay ran out); the source is finished
};

/// Counts a source keeps about what it refused or missed.
struct InputSourceStats {
  std::uint64_t frames = 0;           ///< frames delivered
  std::uint64_t rejectedReports = 0;  ///< reports refused (short, unknown ID)
  std::uint64_t droppedBursts = 0;    ///< kernel buffer overruns (SYN_DROPPED) recovered by a resync
};

/// A device that delivers input frames. Owned and read by one thread.
class InputSource {
 public:
  virtual ~InputSource() = default;
  /// The device and its controls. Valid for the source's lifetime.
  virtual const DeviceDescription& description() const noexcept = 0;
  /// Waits up to `timeout` for input; appends complete frames (values, then a Sync) to `out`.
  /// Never blocks longer than `timeout`. Not RT-safe (it is the input thread's blocking call).
  virtual ReadResult read(std::vector<InputEvent>& out, Nanoseconds timeout) = 0;
  /// Counters since the source was opened.
  virtual InputSourceStats stats() const noexcept { return {}; }
};

}  // namespace fieldcast::io
