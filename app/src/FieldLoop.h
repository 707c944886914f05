#pragma once
// The field thread (DESIGN.md §4–§5): sleeps to each field's absolute wake-up, takes the newest
// complete frame without waiting, asks the motion model for the pose at the field's display
// time, warps, and hands the field to the sinks. Never allocates, never blocks on the renderer,
// the sinks or the input; a field that cannot be made in time is counted and skipped. Each emitted
// field goes to the per-field record (FieldLog) when there is one, and with a host the arrival of
// the sample its pose was made from → the field is measured (Measure::HostToEmission/ToDisplay).

#include <service/ServiceMetrics.h>

#include <fieldcast/Field.h>
#include <fieldcast/Time.h>
#include <io_bridge/SinkHub.h>
#include <motion/HostMotion.h>
#include <motion/MotionSource.h>
#include <prp_warp/FieldClock.h>
#include <prp_warp/FieldWarper.h>
#include <prp_warp/TripleBuffer.h>

#include <atomic>
#include <cstdint>
#include <functional>

namespace fieldcast::app {

/// Instant of the newest control input not yet reflected in a field, for stick → field latency.
/// The input thread stores the event's kernel timestamp; the field loop takes it. 0: none pending.
using PendingInput = std::atomic<std::int64_t>;

class FieldLoop {
 public:
  /// Every reference must outlive the loop. `pendingInput` may be null (no stick). The warper's
  /// counts so far (a warm-up) are not reported; only what it counts from here.
  FieldLoop(warp::FieldClock& clock, const Clock& timeSource, warp::FieldWarper& warper, warp::FrameHandover& frames,
            const motion::MotionSource& motion, io::SinkHub& sinks, ServiceMetrics& metrics,
            PendingInput* pendingInput = nullptr);

  /// Emits fields until `stop` is set, the next field's display time is `end` or later, or
  /// `fieldCount` fields of the schedule (emitted or missed; 0: no limit) have passed. When the
  /// schedule ends (not a stop), the fields of it skipped at its end are counted missed and the
  /// sinks are told where it ended (SinkHub::endSchedule). Field thread body. RT-safe after the
  /// first field.
  void run(const std::atomic<bool>& stop, TimePoint end = TimePoint::max(), std::uint64_t fieldCount = 0) noexcept;

  /// Makes one field for `tick` and publishes it (the body of run(); exposed for virtual-time tests).
  void emit(const warp::FieldTick& tick) noexcept;

  /// Called at the start of every field, before the pose is asked for (the stick flight model
  /// steps here). Must be RT-safe. Set before run().
  using BeforeField = std::function<void(const warp::FieldTick&)>;
  void setBeforeField(BeforeField hook) { mBeforeField = std::move(hook); }

 private:
  /// Counts `missed` fields of the schedule as missed (and those of the first second apart).
  void countMissed(std::uint64_t missed) noexcept;
  /// The schedule ends at `tick` (past `end` or `fieldCount`): counts the fields skipped before it
  /// that were still in the schedule and tells the sinks where it ended.
  void endSchedule(const warp::FieldTick& tick, TimePoint end, std::uint64_t fieldCount) noexcept;
  /// The pose at the field's display time and, with a host (ServiceMetrics::hostSamples), the
  /// sample it was made from (`used` stays invalid otherwise). RT-safe.
  Pose poseAt(TimePoint displayTime, motion::HostSampleUsed& used) const noexcept;

  warp::FieldClock& mClock;
  const Clock& mTime;
  warp::FieldWarper& mWarper;
  warp::FrameHandover& mFrames;
  const motion::MotionSource& mMotion;
  io::SinkHub& mSinks;
  ServiceMetrics& mMetrics;
  PendingInput* mPendingInput;
  BeforeField mBeforeField;
  Field mField;                          // reused for every field: allocated once at construction
  Frame mNoFrame;                        // the empty frame warped (to black) before the first frame arrives
  std::uint64_t mFirstSecondFields = 0;  // fields in the run's first second
  std::uint64_t mScheduled = 0;          // fields of the schedule so far, emitted or missed
  std::uint64_t mLastFieldNumber = 0;    // of the last field made
  // The warper's totals already reported (from construction: a warm-up before is not counted).
  std::uint64_t mLastFallbacks = 0;
  std::uint64_t mLastFallbacksByReason[4] = {};
  std::uint64_t mLastViolations = 0;
  motion::HostSampleUsed mLastHostSample;  // of the previous emitted field: a new one starts a latency
};

}  // namespace fieldcast::app
