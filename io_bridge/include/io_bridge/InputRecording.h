#pragma once
// Record any input source to a file and replay it as a source, so flights and latency tests are
// repeatable: replaying a recording through the same profile gives bit-identical ControlStates.
//
// File format (text, one record per line, fields separated by one space; documented in
// io_bridge/README.md):
//   fieldcast-input 1
//   device <transport> <vendor hex4> <product hex4> <name to end of line>
//   control <usage hex8> <axis|button|hat> <min> <max>      (one line per control)
//   v <t_ns> <usage hex8> <value>                            (a value)
//   s <t_ns>                                                 (end of a frame)
//   lost <t_ns> / found <t_ns>                               (device lost / back)
// Lines starting with '#' are comments. Times are CLOCK_MONOTONIC nanoseconds as captured.

#include <io_bridge/InputSource.h>

#include <fieldcast/Time.h>

#include <filesystem>
#include <fstream>
#include <istream>
#include <span>
#include <string>
#include <vector>

namespace fieldcast::io {

/// Appends a device's events to a recording file. Input thread only; not RT-safe (file I/O).
class InputRecorder {
 public:
  /// Creates (truncates) `path` and writes the header for `device`. Throws naming the path.
  InputRecorder(const std::filesystem::path& path, const DeviceDescription& device);
  /// Appends events (values, syncs, lost/found markers).
  void write(std::span<const InputEvent> events);
  /// Pushes buffered lines to the file.
  void flush();
  const std::filesystem::path& path() const noexcept { return mPath; }

 private:
  std::filesystem::path mPath;
  std::ofstream mOut;
};

/// A parsed recording.
struct InputRecording {
  DeviceDescription device;
  std::vector<InputEvent> events;
};

/// Reads a recording. Throws std::runtime_error naming "file:line: what was expected".
InputRecording readInputRecording(const std::filesystem::path& path);
/// Parses a recording from a stream; `origin` names it in errors. Throws as readInputRecording.
InputRecording parseInputRecording(std::istream& in, const std::string& origin);

/// How a replay is paced.
enum class ReplayPacing : std::uint8_t {
  AsFastAsPossible,  ///< every read() returns the next frame at once; times as recorded
  RealTime,          ///< frames are released at their recorded spacing, times moved to the replay's clock
};

/// A recording played back as an input source. Ends with ReadResult::End (or Lost where the
/// recording says the device was lost).
class ReplaySource final : public InputSource {
 public:
  ReplaySource(InputRecording recording, ReplayPacing pacing, Clock& clock);
  /// Reads `path` (throws as readInputRecording).
  ReplaySource(const std::filesystem::path& path, ReplayPacing pacing, Clock& clock);

  const DeviceDescription& description() const noexcept override { return mRecording.device; }
  ReadResult read(std::vector<InputEvent>& out, Nanoseconds timeout) override;
  InputSourceStats stats() const noexcept override { return {mFrames, 0, 0}; }

 private:
  InputRecording mRecording;
  ReplayPacing mPacing;
  Clock& mClock;
  std::size_t mNext = 0;
  std::uint64_t mFrames = 0;
  bool mStarted = false;
  std::int64_t mShiftNs = 0;  // replay time − recorded time (RealTime pacing)
};

}  // namespace fieldcast::io
