#include "FieldLoop.h"

#include "FieldLog.h"

#include <motion/HostMotion.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <limits>

namespace fieldcast::app {

FieldLoop::FieldLoop(warp::FieldClock& clock, const Clock& timeSource, warp::FieldWarper& warper,
                     warp::FrameHandover& frames, const motion::MotionSource& motion, io::SinkHub& sinks,
                     ServiceMetrics& metrics, PendingInput* pendingInput)
    : mClock(clock),
      mTime(timeSource),
      mWarper(warper),
      mFrames(frames),
      mMotion(motion),
      mSinks(sinks),
      mMetrics(metrics),
      mPendingInput(pendingInput),
      mField(warper.makeField()) {
  const auto& totals = warper.counters();
  mFirstSecondFields = static_cast<std::uint64_t>(std::chrono::seconds(1) / clock.period());
  mLastFallbacks = totals.fitFallbacks.load(std::memory_order_relaxed);
  for (int r = 0; r < 4; ++r)
    mLastFallbacksByReason[r] = totals.fallbacksByReason[r + 1].load(std::memory_order_relaxed);
  mLastViolations = totals.marginViolations.load(std::memory_order_relaxed);
}

void FieldLoop::run(const std::atomic<bool>& stop, TimePoint end, std::uint64_t fieldCount) noexcept {
  while (!stop.load(std::memory_order_acquire)) {
    const warp::FieldTick tick = mClock.next();
    if (stop.load(std::memory_order_acquire)) break;
    const bool counted = fieldCount != 0 && mScheduled + 1 + tick.missedBefore > fieldCount;
    if (tick.displayTime >= end || counted) {
      endSchedule(tick, end, fieldCount);
      break;
    }
    emit(tick);
  }
}

void FieldLoop::endSchedule(const warp::FieldTick& tick, TimePoint end, std::uint64_t fieldCount) noexcept {
  // The fields skipped before this tick that still lie in the schedule were missed at its end.
  const std::uint64_t firstSkipped = tick.fieldNumber - tick.missedBefore;
  std::uint64_t inSchedule = 0;
  while (inSchedule < tick.missedBefore && mClock.displayTime(firstSkipped + inSchedule) < end &&
         (fieldCount == 0 || mScheduled + inSchedule < fieldCount))
    ++inSchedule;
  countMissed(inSchedule);
  if (mScheduled == inSchedule) return;  // no field made: nothing for the sinks to complete
  // A tick renumbered by a move onto another lock counts in a numbering no sink has seen: the
  // schedule ends after the last field made (its skipped fields, if any, still counted missed).
  mSinks.endSchedule(tick.renumbered ? mLastFieldNumber + 1 : firstSkipped + inSchedule);
}

void FieldLoop::countMissed(std::uint64_t missed) noexcept {
  if (missed == 0) return;
  ServiceCounters& counters = mMetrics.counters;
  counters.fieldsMissed.fetch_add(missed, std::memory_order_relaxed);
  // As far as they lie in the first second of the schedule.
  if (mScheduled < mFirstSecondFields) {
    const std::uint64_t early = std::min(mScheduled + missed, mFirstSecondFields) - mScheduled;
    counters.fieldsMissedFirstSecond.fetch_add(early, std::memory_order_relaxed);
  }
  mScheduled += missed;
}

void FieldLoop::emit(const warp::FieldTick& tick) noexcept {
  const TimePoint start = mTime.now();
  ServiceCounters& counters = mMetrics.counters;
  // The schedule's first field: the sinks learn where it starts, so fields missed before the
  // first one made are not lost to them either.
  if (mScheduled == 0) mSinks.beginSchedule(tick.fieldNumber - tick.missedBefore);
  // Counted by the schedule, not by field numbers: a channel joining a frame lock starts at the
  // others' number, and a move onto another lock renumbers the fields
  countMissed(tick.missedBefore);
  ++mScheduled;
  mLastFieldNumber = tick.fieldNumber;
  mMetrics.record(Measure::FieldJitter, Nanoseconds{std::abs((start - tick.wakeTime).count())});

  if (mBeforeField) mBeforeField(tick);
  // Take the newest complete frame; keep the one we have if nothing newer arrived.
  mFrames.update();
  const Frame& frame = mFrames.hasTaken() ? mFrames.front() : mNoFrame;
  // The pose below is computed now, so every input that arrived before this instant is reflected.
  const std::int64_t inputNs = mPendingInput != nullptr ? mPendingInput->exchange(0, std::memory_order_acq_rel) : 0;
  motion::HostSampleUsed hostSample;
  const Pose pose = poseAt(tick.displayTime, hostSample);
  const warp::FieldStatus status = mWarper.produce(frame, pose, warp::FieldSpec::of(tick), mField);
  // The warper counts in totals; the service reports deltas in its own counters.
  const auto& warpCounters = mWarper.counters();
  const std::uint64_t fallbacks = warpCounters.fitFallbacks.load(std::memory_order_relaxed);
  const std::uint64_t violations = warpCounters.marginViolations.load(std::memory_order_relaxed);
  const std::uint64_t fieldViolations = violations - mLastViolations;
  counters.marginViolations.fetch_add(fieldViolations, std::memory_order_relaxed);
  mLastViolations = violations;

  if (status == warp::FieldStatus::Ok) {
    mMetrics.record(Measure::FrameAge, tick.displayTime - frame.poseTime);
  } else if (status == warp::FieldStatus::NoFrame || status == warp::FieldStatus::BadFrame) {
    counters.fieldsBlack.fetch_add(1, std::memory_order_relaxed);
  } else if (status == warp::FieldStatus::Held) {
    counters.fieldsHeld.fetch_add(1, std::memory_order_relaxed);
  }
  if (status != warp::FieldStatus::BadOutput) {
    mSinks.publish(mField);
    const TimePoint emitted = mTime.now();
    counters.fieldsEmitted.fetch_add(1, std::memory_order_relaxed);
    if (emitted > tick.displayTime) counters.fieldsLate.fetch_add(1, std::memory_order_relaxed);
    if (hostSample.valid && !(hostSample == mLastHostSample)) {
      // The first emitted field made from this sample: arrival → this field.
      mMetrics.record(Measure::HostToEmission, emitted - hostSample.arrival);
      mMetrics.record(Measure::HostToDisplay, tick.displayTime - hostSample.arrival);
      mLastHostSample = hostSample;
    }
    if (FieldLog* log = mMetrics.fieldLog()) {
      FieldRecord r;
      r.fieldNumber = tick.fieldNumber;
      r.displayNs = tick.displayTime.time_since_epoch().count();
      r.emittedNs = emitted.time_since_epoch().count();
      r.pose = pose;
      r.frameNumber = frame.frameNumber;
      r.framePoseNs = frame.poseTime.time_since_epoch().count();
      r.black = status == warp::FieldStatus::NoFrame || status == warp::FieldStatus::BadFrame;
      r.marginPx = static_cast<std::uint32_t>(
          std::min<std::uint64_t>(fieldViolations, std::numeric_limits<std::uint32_t>::max()));
      r.hasHostSample = hostSample.valid;
      r.hostFrame = hostSample.hostFrame;
      r.hostArrivalNs = hostSample.arrival.time_since_epoch().count();
      (void)log->push(r);  // a full ring counts the drop
    }
  }
  if (inputNs != 0) {
    mMetrics.record(Measure::StickLatency, tick.displayTime - TimePoint{Nanoseconds{inputNs}});
  }
  if (fallbacks != mLastFallbacks) {  // the warper counts a reason with every fallback, on this thread
    counters.warpFallbacks.fetch_add(fallbacks - mLastFallbacks, std::memory_order_relaxed);
    mLastFallbacks = fallbacks;
    for (int r = 0; r < 4; ++r) {
      const std::uint64_t byReason = warpCounters.fallbacksByReason[r + 1].load(std::memory_order_relaxed);
      counters.warpFallbacksByReason[r].fetch_add(byReason - mLastFallbacksByReason[r], std::memory_order_relaxed);
      mLastFallbacksByReason[r] = byReason;
    }
  }
  mMetrics.record(Measure::WarpTime, mTime.now() - start);
}

Pose FieldLoop::poseAt(TimePoint displayTime, motion::HostSampleUsed& used) const noexcept {
  const motion::HostMotion* host = mMetrics.hostSamples();
  if (host == nullptr) return mMotion.poseAt(displayTime);
  // The sample before and after the pose: equal, the pose was made from it. When the receiver
  // added one in between (microseconds apart, so at most once in practice), ask again.
  used = host->sampleUsedAt(displayTime);
  Pose pose;
  for (int attempt = 0; attempt < 3; ++attempt) {
    pose = mMotion.poseAt(displayTime);
    const motion::HostSampleUsed after = host->sampleUsedAt(displayTime);
    if (after == used) break;
    used = after;
  }
  return pose;
}

}  // namespace fieldcast::app
