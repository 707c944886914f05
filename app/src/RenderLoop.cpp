#include "RenderLoop.h"

#include <prp_warp/PostProcess.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <thread>

namespace fieldcast::app {

RenderLoop::RenderLoop(core::Renderer& renderer, const motion::MotionSource& motion, const Intrinsics& display,
                       warp::FrameHandover& frames, ServiceMetrics& metrics, const RenderPacing& pacing,
                       core::TileCache* tiles, TerrainSwitch* terrainSwitch)
    : mRenderer(renderer),
      mMotion(motion),
      mDisplay(display),
      mFrames(frames),
      mMetrics(metrics),
      mPacing(pacing),
      mTiles(tiles),
      mSwitch(terrainSwitch),
      mController(pacing.controller, pacing.initialQuality) {
  mRenderer.setQuality(pacing.initialQuality);
}

RenderLoop::InFlight RenderLoop::submitNext(TimePoint now) {
  // Render for the instant the frame will be ready: the warp then extrapolates over the shortest
  // possible interval (frame → field), which is where the quadratic is most exact.
  const TimePoint poseTime = now + mExpectedLatency;
  if (mPacing.display != nullptr) mDisplay = mPacing.display->load();
  core::ViewRequest request;
  request.pose = mMotion.poseAt(poseTime);
  request.poseTime = poseTime;
  request.display = mDisplay;
  request.frameNumber = mNextFrameNumber++;
  if (mPacing.entities != nullptr) mPacing.entities->at(poseTime, request.entities);
  if (mSwitch != nullptr) {
    core::TileCache* wanted = mSwitch->wanted.load(std::memory_order_acquire);
    if (wanted != nullptr && wanted != mTiles) {
      // The frame in flight keeps the old terrain (and its lease on it) until it is finished.
      mRenderer.setTerrain(wanted->view());
      mTiles = wanted;
      spdlog::info("render: frame {} on is rendered from {}", request.frameNumber, wanted->sourceName());
    }
  }
  InFlight frame;
  frame.tiles = mTiles;
  if (mTiles != nullptr) {
    const Pose ahead = mMotion.poseAt(poseTime + std::chrono::milliseconds(100));
    mTiles->prefetch(request.pose, (ahead.positionM - request.pose.positionM) * 10.0, mDisplay,
                     core::prefetchLod(mRenderer.settings()));
    frame.lease = mTiles->lease();
  }
  if (mPacing.hazeRangeM != nullptr) {
    const double haze = mPacing.hazeRangeM->load(std::memory_order_relaxed);
    if (haze > 0.0 && haze != mRenderer.settings().hazeRangeM) {
      core::RenderSettings settings = mRenderer.settings();
      settings.hazeRangeM = haze;
      mRenderer.setSettings(settings);  // applies to this frame on: in-flight frames keep theirs
    }
  }
  if (mPacing.sun != nullptr) {
    const std::optional<core::SunDirection> sun = mPacing.sun->load();
    if (sun && !(*sun == mRenderer.settings().sun)) {
      core::RenderSettings settings = mRenderer.settings();
      settings.sun = *sun;
      mRenderer.setSettings(settings);
    }
  }
  // The producer's spare slot holds a frame the field thread has let go of: its buffers are reused.
  frame.ticket = mRenderer.submit(request, std::move(mFrames.back()));
  return frame;
}

void RenderLoop::finish(InFlight& frame) {
  core::RenderStats stats;
  Frame done = mRenderer.finish(std::move(frame.ticket), &stats);
  frame.lease.release();
  if (mSwitch != nullptr) mSwitch->settled.store(frame.tiles, std::memory_order_release);
  publish(std::move(done), stats);
}

void RenderLoop::publish(Frame&& frame, const core::RenderStats& stats) {
  if (mPacing.flickerFilter) {
    // Once per frame here, beside the workers, rather than in the field thread's next field. The
    // frame is complete with its copy: the render time and the expected latency include it.
    warp::makeFlickerFiltered(frame);
    frame.renderEnd = MonotonicClock::now();
  }
  const TimePoint submitted = frame.renderStart;
  const TimePoint completed = frame.renderEnd;
  const Nanoseconds took = completed - submitted;
  mMetrics.record(Measure::RenderTime, took);
  // Smooth the submit → ready latency (renderStart is the submit; with frames overlapping it
  // exceeds the frame's own work).
  mExpectedLatency = Nanoseconds{(mExpectedLatency.count() * 7 + std::max<std::int64_t>(took.count(), 0)) / 8};
  mFrames.back() = std::move(frame);
  mFrames.publish();
  mPublished.fetch_add(1, std::memory_order_release);
  mMetrics.recordFrame(stats.quality, stats.maxAnisotropy > 0.0);
  if (mPacing.controller.target.count() > 0) {
    // Not `took`: with two frames in flight that is about two frame times (see update()).
    const double q = mController.update(core::RenderedFrame{submitted, completed, stats.quality, stats.maxAnisotropy});
    mRenderer.setQuality(q);
    if (mPacing.controller.grazingAnisotropy > 0.0) mRenderer.setMaxAnisotropy(mController.maxAnisotropy());
  }
}

bool RenderLoop::run(std::atomic<bool>& stop) noexcept {
  try {
    const Nanoseconds minInterval = mPacing.maxRateHz > 0 ? fromSeconds(1.0 / mPacing.maxRateHz) : Nanoseconds{0};
    SystemClock clock;
    TimePoint nextStart = clock.now();
    // Two frames in flight: while the loop waits for one, the workers already cast the next.
    InFlight inFlight;
    while (!stop.load(std::memory_order_acquire)) {
      if (minInterval.count() > 0) {
        clock.sleepUntil(nextStart);
        nextStart = std::max(nextStart + minInterval, clock.now() - minInterval);
      }
      InFlight next = submitNext(clock.now());
      if (inFlight.ticket) finish(inFlight);
      inFlight = std::move(next);
      // A capped IG hands each frame over as soon as it is ready, not one frame later.
      if (minInterval.count() > 0) finish(inFlight);
    }
    if (inFlight.ticket) mRenderer.finish(std::move(inFlight.ticket));
    return true;
  } catch (const std::exception& e) {
    spdlog::critical("render thread: {}", e.what());
  } catch (...) {
    spdlog::critical("render thread: unknown exception");
  }
  stop.store(true, std::memory_order_release);
  return false;
}

}  // namespace fieldcast::app
