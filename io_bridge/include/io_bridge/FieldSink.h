#pragma once
// The one interface every field output implements (Y4M, RTP, image files, window, shared memory,
// GPIO pulse). A SinkHub drives each sink from its own worker thread, so a sink may block (write
// to a pipe, pace packets, sleep to a pulse edge) without ever holding up the field thread.

#include <io_bridge/StreamFormat.h>

#include <fieldcast/Field.h>

#include <cstdint>
#include <string>

namespace fieldcast::io {

/// What a sink says after consuming a field.
enum class SinkStatus : std::uint8_t {
  Ok,     ///< keep feeding me
  Ended,  ///< the sink is finished for good (broken pipe, consumer gone); see endReason()
};

/// A field output. All calls but wants() come from the one worker thread that owns the sink, in
/// the order open → [scheduleStarted] → consume* → [scheduleEnded] → close; a sink therefore needs
/// no locking of its own beyond what wants() reads.
class FieldSink {
 public:
  virtual ~FieldSink() = default;
  FieldSink() = default;
  FieldSink(const FieldSink&) = delete;
  FieldSink& operator=(const FieldSink&) = delete;

  /// Short name for logs and figures ("y4m", "rtp", …).
  virtual std::string name() const = 0;
  /// Prepares the output for `format` (opens files and sockets, allocates every buffer). Called
  /// on the worker thread before the first field. Throws with a message naming the resource and
  /// what went wrong; the hub then refuses to start.
  virtual void open(const StreamFormat& format) = 0;
  /// Whether the sink takes `field` at all. Asked on the field thread before the field is queued,
  /// so a sink that keeps only some fields (a still every N fields) costs no copy between them and
  /// cannot lose the ones it keeps to a queue filled with fields it would pass over. Runs on the
  /// field thread beside the worker: must be RT-safe and read only what the constructor set, or
  /// atomics. The default takes every field.
  virtual bool wants(const Field& field) const noexcept {
    (void)field;
    return true;
  }
  /// Emits one field (which matches the format given to open()). May block; must not throw for
  /// a consumer going away: return Ended and say why in endReason().
  virtual SinkStatus consume(const Field& field) = 0;
  /// The run's schedule starts at field number `firstField`: a first field consumed with a higher
  /// number was preceded by fields that never came (a stall at the run's start). Called before the
  /// first consume() when the field thread said where its schedule starts. The default does nothing.
  virtual void scheduleStarted(std::uint64_t firstField) { (void)firstField; }
  /// The run's schedule ended just before field number `firstFieldAfter`: fields numbered below it
  /// that never came were missed at the end of the run (a stall in its last fields). Called after
  /// the last consume() and before close(), only when the run ended by its schedule (--duration,
  /// a flight's end), not when it was stopped. A sink whose output keeps time by counting
  /// (a Y4M file) fills them; the default does nothing.
  virtual void scheduleEnded(std::uint64_t firstFieldAfter) { (void)firstFieldAfter; }
  /// Flushes and releases the output (completes a half-written frame where the format needs it).
  virtual void close() = 0;
  /// Why consume() returned Ended; empty otherwise.
  virtual std::string endReason() const { return {}; }
};

}  // namespace fieldcast::io
