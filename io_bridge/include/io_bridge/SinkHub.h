#pragma once
// The fan-out from the field thread to the sinks. publish() copies the field once into a free
// slot of a preallocated pool, queues that slot on each sink's bounded queue and wakes that sink's
// worker; it never waits, never allocates and never fails. A field no sink wants
// (FieldSink::wants) is not copied. A sink whose queue is full loses that field (counted); a
// sink that ends (broken pipe) is logged once and skipped from then on, and the service carries on.

#include <io_bridge/FieldSink.h>
#include <io_bridge/StreamFormat.h>

#include <fieldcast/Field.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace fieldcast::io {

/// Figures of one sink, read at any time from any thread.
struct SinkFigures {
  std::string name;
  std::uint64_t published = 0;     ///< fields offered to the sink
  std::uint64_t passedOver = 0;    ///< fields it did not want (FieldSink::wants): neither queued nor lost
  std::uint64_t consumed = 0;      ///< fields the sink has finished with
  std::uint64_t droppedFull = 0;   ///< fields lost because the sink's queue was full
  std::uint64_t rejected = 0;      ///< fields that did not match the stream format
  std::uint64_t maxConsumeNs = 0;  ///< longest consume() call
  std::uint64_t totalConsumeNs = 0;
  bool realtime = false;  ///< its worker runs SCHED_FIFO (asked for and granted)
  bool ended = false;     ///< the sink has stopped for good
  std::string endReason;  ///< why, when ended
};

/// Queue depth and other knobs of a SinkHub.
struct SinkHubOptions {
  int queueDepth = 3;  ///< fields each sink may have waiting (1–64); more absorbs longer stalls
};

/// How one sink's worker runs.
struct SinkWorkerOptions {
  /// SCHED_FIFO priority (1–99) for the worker, e.g. for the GPIO pulse whose edges must be on
  /// time; 0 keeps the normal scheduler. A refusal (no CAP_SYS_NICE / rtprio limit) is logged
  /// once and the sink runs anyway.
  int realtimePriority = 0;
};

/// Owns the sinks and one worker thread per sink.
class SinkHub {
 public:
  /// Throws std::invalid_argument for a format that cannot be streamed.
  explicit SinkHub(StreamFormat format, SinkHubOptions options = {});
  ~SinkHub();  ///< stops (draining the queues) if still running
  SinkHub(const SinkHub&) = delete;
  SinkHub& operator=(const SinkHub&) = delete;

  /// Adds a sink before start(). Not RT-safe.
  void add(std::unique_ptr<FieldSink> sink, SinkWorkerOptions worker = {});
  /// Preallocates the field pool (queueDepth × sinks + 1 full-size fields), starts one worker
  /// per sink and waits until every sink has opened. If any open() throws, all
  /// workers are stopped and std::runtime_error names each sink that failed and why.
  void start();
  /// Offers a field to every live sink that wants it. Field thread only. RT-safe: no lock, no
  /// allocation, no wait; costs one copy of the field, whatever the number of sinks, and none when
  /// no sink wants it.
  void publish(const Field& field) noexcept;
  /// Tells every sink, before the first field it consumes, that the schedule starts at field
  /// `firstField` (FieldSink::scheduleStarted). Field thread, before its first publish(). RT-safe.
  void beginSchedule(std::uint64_t firstField) noexcept;
  /// Tells every sink, once it has consumed the fields already published, that the schedule
  /// ended just before field `firstFieldAfter` (FieldSink::scheduleEnded). Field thread, after
  /// its last publish(); takes effect at stop(). RT-safe.
  void endSchedule(std::uint64_t firstFieldAfter) noexcept;
  /// Lets every sink finish the fields already queued, closes them and joins the workers.
  /// Idempotent.
  void stop();

  /// Figures of every sink, in the order added. Any thread.
  std::vector<SinkFigures> figures() const;
  /// Total fields lost over all sinks (queue full or rejected). Any thread, RT-safe.
  std::uint64_t droppedTotal() const noexcept;
  /// One line per sink for the log: "images: 12 fields, 3584 passed over, 0 dropped (queue full),
  /// 0 rejected, mean 66 ms, max 114 ms" (passed over only when some were).
  std::string summary() const;
  const StreamFormat& format() const noexcept { return mFormat; }

 private:
  struct Lane;
  struct Pool;
  void allocatePool();
  StreamFormat mFormat;
  SinkHubOptions mOptions;
  std::vector<std::unique_ptr<Lane>> mLanes;
  std::unique_ptr<Pool> mPool;
  std::vector<std::uint8_t> mTakes;  // per publish: which lanes take the field (sized at start)
  bool mRunning = false;
};

}  // namespace fieldcast::io
