#pragma once
// The service's figures (issue 8): counters and duration histograms that the field thread and the
// render loop record into without locks or allocation, a one-line report per interval for the
// log, and the run summary (also written as JSON for scripts).

#include <service/Histogram.h>

#include <fieldcast/Time.h>

#include <nlohmann/json_fwd.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

namespace fieldcast::motion {
class HostMotion;
}

namespace fieldcast::app {

class FieldLog;

/// Durations the service measures. Each is recorded into its interval histogram; every report
/// drains the interval into the run total.
enum class Measure : std::uint8_t {
  RenderTime,      ///< render start → frame complete
  WarpTime,        ///< field thread: warp + post-processing + hand-off to the sinks
  FrameAge,        ///< field display time − the pose time of the frame it was warped from
  FieldJitter,     ///< |field emission − its scheduled emission instant|
  StickLatency,    ///< stick event timestamp → display time of the first field reflecting it
  HostToEmission,  ///< host datagram arrival → emission of the first field whose pose uses its sample
  HostToDisplay,   ///< host datagram arrival → display time of that field
  kCount
};

/// Monotonic counters (any thread, relaxed atomics).
struct ServiceCounters {
  std::atomic<std::uint64_t> framesRendered{0};
  std::atomic<std::uint64_t> fieldsEmitted{0};  ///< fields handed to the sinks, black ones included
  std::atomic<std::uint64_t> fieldsBlack{0};    ///< emitted before the first frame existed
  std::atomic<std::uint64_t> fieldsHeld{0};     ///< the previous picture again: the pose was beyond the frame's reach
  std::atomic<std::uint64_t> fieldsMissed{0};   ///< deadlines passed without a field
  /// Handed to the sinks after their display time: an output clocked to the display times shows
  /// them a field late (the work started in time, the warp or the machine took too long).
  std::atomic<std::uint64_t> fieldsLate{0};
  /// Output pixels sampled outside the frame (outside its footprint, for a rolled one)
  std::atomic<std::uint64_t> marginViolations{0};
  std::atomic<std::uint64_t> warpFallbacks{0};  ///< fields warped by the rotation-only fallback
  /// warpFallbacks by reason: few points, all sky, degenerate, no range image (FallbackReason − 1).
  std::atomic<std::uint64_t> warpFallbacksByReason[4]{};
  std::atomic<std::uint64_t> fieldsMissedFirstSecond{0};  ///< of fieldsMissed, those of the run's first second
  std::atomic<std::uint64_t> qualityMilliSum{0};          ///< frames' quality knobs × 1000, summed (see recordFrame)
  std::atomic<std::uint64_t> framesGrazing{0};            ///< frames rendered with the grazing-angle rule on
};

/// How the run started (the field clock's start-up, DESIGN.md §4): set once, before the first field.
struct StartupFigures {
  double toFirstFieldS = 0.0;     ///< Service::start() → the first field's wake-up
  double warmUpWarpMs = 0.0;      ///< the field thread's warm-up warp (before the field clock started)
  std::uint64_t warmUpFrame = 0;  ///< number of the frame it warped (0: none)
  bool memoryLocked = false;      ///< mlockall(MCL_CURRENT | MCL_FUTURE) granted
  std::uint64_t tileMisses = 0;   ///< terrain samples answered by a coarser level before the first field
};

/// Figures of the whole run, for --summary and the end-of-run log.
struct ServiceFigures {
  double durationS = 0.0;
  std::uint64_t framesRendered = 0;
  std::uint64_t fieldsEmitted = 0;
  std::uint64_t fieldsBlack = 0;
  std::uint64_t fieldsHeld = 0;
  std::uint64_t fieldsMissed = 0;
  std::uint64_t fieldsLate = 0;
  std::uint64_t marginViolations = 0;
  std::uint64_t warpFallbacks = 0;
  std::uint64_t fallbacksFewPoints = 0, fallbacksAllSky = 0, fallbacksDegenerate = 0, fallbacksNoRange = 0;
  std::uint64_t fieldsMissedFirstSecond = 0;
  StartupFigures startup;
  std::uint64_t tileMissesRun = 0;  ///< tile misses after the start-up (startup.tileMisses before it)
  double visibilityM = 0.0;         ///< the haze range rendered with
  double meanQuality = 0.0;         ///< mean quality knob over the frames rendered (0 when none)
  std::uint64_t framesGrazing = 0;
  DurationSummary render, warp, frameAge, jitter, stickLatency;
  DurationSummary hostToEmission, hostToDisplay;  ///< motion.source = "host" (see Measure)
  std::string fieldLogPath;                       ///< metrics.field_log (empty: none)
  std::uint64_t fieldLogRecords = 0;              ///< lines written to it
  std::uint64_t fieldLogDropped = 0;              ///< records lost to a full ring (the writer fell behind)
};

class ServiceMetrics {
 public:
  ServiceMetrics();
  ~ServiceMetrics();

  ServiceCounters counters;  ///< any thread

  /// Starts the run's clock at `start` (the first field), so figures per second count the run,
  /// not the start-up. Call before the threads record.
  void startAt(TimePoint start) noexcept { mStart = mLast = start; }

  /// Records a duration. Any thread; wait-free, RT-safe.
  void record(Measure m, Nanoseconds d) noexcept { mInterval[static_cast<int>(m)].record(d); }

  /// Counts a rendered frame (framesRendered) with its knobs (RenderStats): the frame-time
  /// controller's quality and whether the grazing-angle rule was on. Any thread; wait-free,
  /// RT-safe. The knobs are published after the frame, and intervalLine reads them first, so an
  /// interval never holds more knobs than frames.
  void recordFrame(double quality, bool grazing) noexcept {
    counters.framesRendered.fetch_add(1, std::memory_order_relaxed);
    if (grazing) counters.framesGrazing.fetch_add(1, std::memory_order_release);
    counters.qualityMilliSum.fetch_add(static_cast<std::uint64_t>(std::lround(quality * 1000.0)),
                                       std::memory_order_release);
  }

  /// The line for the log since the previous call (render Hz, fields, missed, margin, warp
  /// p50/p99, frame age, stick latency when any, the mean quality knob and grazing-rule share when
  /// frames were rendered), then folds the interval into the totals.
  /// Call from one thread (the metrics/main thread).
  std::string intervalLine(TimePoint now);

  /// Records how the run started and the terrain's tile-miss total at the first field (the
  /// start-up's misses). Call once, before the first field, from the thread that starts them.
  void setStartup(const StartupFigures& startup) noexcept {
    mStartup = startup;
    mLastTileMisses = startup.tileMisses;
  }
  /// The tile misses since the previous call (the first call: since the start-up), given the
  /// terrain's running total (TileCacheStats::viewMisses). Call from the intervalLine thread.
  std::uint64_t tileMissesSince(std::uint64_t total) noexcept {
    const std::uint64_t delta = total >= mLastTileMisses ? total - mLastTileMisses : 0;
    mLastTileMisses = std::max(total, mLastTileMisses);
    return delta;
  }
  /// The haze range the frames are rendered with, for the summary.
  void setVisibility(double visibilityM) noexcept { mVisibilityM = visibilityM; }

  /// Opens the per-field record (FieldLog) at `path` and starts its writer: the path is checked
  /// now. Throws std::runtime_error naming metrics.field_log. Call before the fields start.
  void openFieldLog(const std::filesystem::path& path);
  /// Stops the record's writer and closes the file once the fields have stopped (its counts stay
  /// in figures()). Throws when the file could not be written. No-op without a record.
  void closeFieldLog();
  /// The per-field record, or null. The field thread is its one producer.
  FieldLog* fieldLog() noexcept { return mFieldLog.get(); }
  /// With motion.source = "host": where the field thread asks which sample each pose was made
  /// from (the field record's host columns, HostToEmission and HostToDisplay). Set before the
  /// fields start; must outlive them.
  void setHostSamples(const motion::HostMotion* host) noexcept { mHostSamples = host; }
  const motion::HostMotion* hostSamples() const noexcept { return mHostSamples; }

  /// Render rate of the last interval reported by intervalLine(), Hz.
  double lastRenderHz() const noexcept { return mLastRenderHz; }

  /// The run so far (drains the open interval first). Call from the thread that calls intervalLine.
  ServiceFigures figures(TimePoint now);

 private:
  DurationHistogram mInterval[static_cast<int>(Measure::kCount)];
  DurationHistogram mTotal[static_cast<int>(Measure::kCount)];
  DurationHistogram mScratch;
  TimePoint mStart;
  TimePoint mLast;
  std::uint64_t mLastFrames = 0;
  std::uint64_t mLastFields = 0;
  std::uint64_t mLastMissed = 0;
  std::uint64_t mLastMargin = 0;
  std::uint64_t mLastQualityMilli = 0;
  std::uint64_t mLastGrazing = 0;
  double mLastRenderHz = 0.0;
  StartupFigures mStartup;
  std::uint64_t mLastTileMisses = 0;
  double mVisibilityM = 0.0;
  std::unique_ptr<FieldLog> mFieldLog;
  const motion::HostMotion* mHostSamples = nullptr;
};

/// The figures as JSON (seconds, counts), with `extra` fields merged at the top level.
nlohmann::json toJson(const ServiceFigures& figures);

/// Human summary of the run (a few lines).
std::string describe(const ServiceFigures& figures);

}  // namespace fieldcast::app
