#include "Channel.h"

#include "MemoryLock.h"
#include "ThreadScheduling.h"

#include <ig_core/Renderer.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

namespace fieldcast::app {

namespace {

// The largest frame the renderer makes for `display` at any roll: the warp turns the window about
// the view axis, and the frame must hold it. A centred 4:3 window's diagonal (1.7 × its width); a
// window far off the axis, which a roll swings round the axis, more.
core::FrameLayout largestFrame(const Intrinsics& display, double marginFraction) noexcept {
  core::FrameLayout largest = core::layoutFrame(display, marginFraction, 0.0);
  for (int deg = 5; deg <= 180; deg += 5) {
    const core::FrameLayout l = core::layoutFrame(display, marginFraction, radians(deg));
    largest.frame.widthPx = std::max(largest.frame.widthPx, l.frame.widthPx);
    largest.frame.heightPx = std::max(largest.frame.heightPx, l.frame.heightPx);
  }
  return largest;
}

}  // namespace

ChannelSettings channelSettingsOf(const ServiceConfig& config) {
  ChannelSettings s;
  s.view = channelViewOf(config.view, config.render.widthPx, config.render.heightPx, radians(config.render.hfovDeg));
  s.render = config.render;
  s.prp = config.warp;
  s.output = config.output;
  s.sinks = config.sinks;
  s.threads = config.threads;
  return s;
}

Channel::Channel(const ChannelSettings& settings, core::TileCache& terrain, const motion::MotionSource& ownship,
                 Clock& clock, ServiceMetrics& metrics, OnFatal onFatal, std::function<void(int, io::WindowKey)> onKey)
    : mSettings(settings),
      mTerrain(terrain),
      mMotion(ownship, settings.view.offset),
      mDisplay(settings.view.display),
      mClock(clock),
      mMetrics(metrics),
      mOnFatal(std::move(onFatal)) {
  mTerrainSwitch.settled.store(&terrain, std::memory_order_relaxed);
  warp::FieldWarperConfig warper = settings.prp.warper;
  warper.rasterWidthPx = settings.output.widthPx;
  warper.rasterHeightPx = settings.output.heightPx;
  warper.outputFormat = settings.output.pixelFormat;
  // The render loop gives each frame its flicker-filtered copy; the warper's own buffer, for a
  // frame that comes without one, holds the largest frame of the configured window
  const core::FrameLayout largest = largestFrame(settings.view.display, settings.render.settings.marginFraction);
  warper.maxFrameWidthPx = largest.frame.widthPx;
  warper.maxFrameHeightPx = largest.frame.heightPx;
  mWarper = std::make_unique<warp::FieldWarper>(warper);
  io::Sinks sinks = io::makeSinks(settings.sinks, settings.output, std::move(onKey));
  mSinks = std::move(sinks.hub);
  mWindow = sinks.window;
}

Channel::~Channel() {
  try {
    stop();
  } catch (const std::exception& e) {
    spdlog::error("stopping a channel: {}", e.what());
  }
}

void Channel::startOutputs() { mSinks->start(); }

void Channel::startRendering() {
  mRenderThread = std::thread([this] { renderMain(); });
}

void Channel::renderMain() noexcept {
  // Render workers inherit this thread's niceness: on a machine with fewer cores than
  // threads, the field thread then wins the CPU whenever a field is due.
  spdlog::info("{}", applyScheduling("fc-render", ThreadScheduling{false, 0, 5, -1}));
  try {
    const core::RenderConfig& render = mSettings.render;
    core::Renderer renderer(mTerrain.view(), render.settings, render.threads);
    RenderPacing pacing;
    pacing.maxRateHz = render.maxRateHz;
    pacing.controller = render.controller;
    pacing.initialQuality = render.settings.quality;
    pacing.hazeRangeM = mHazeRangeM;
    pacing.sun = mSun;
    pacing.entities = mEntities;
    pacing.display = &mDisplay;
    pacing.flickerFilter = mWarper->config().flickerFilter;
    RenderLoop loop(renderer, mMotion, mSettings.view.display, mFrames, mMetrics, pacing, &mTerrain, &mTerrainSwitch);
    spdlog::info("render: {} worker threads, {}x{} display, margin {:.0f}%", renderer.threads(),
                 mSettings.view.display.widthPx, mSettings.view.display.heightPx, render.settings.marginFraction * 100);
    if (!loop.run(mStopRender)) mOnFatal("render thread stopped (see the log above)");
  } catch (const std::exception& e) {
    mOnFatal(std::string("render: ") + e.what());
  }
}

WarmUp Channel::warmUp() noexcept {
  WarmUp w;
  try {
    Field scratch = mWarper->makeField();
    mFrames.update();
    const Frame* frame = mFrames.hasTaken() ? &mFrames.front() : nullptr;
    if (frame != nullptr) {
      const TimePoint start = mClock.now();
      const TimePoint display = start + mSettings.prp.lead;
      const warp::FieldSpec spec{
          0, display, mSettings.output.scan == ScanMode::Interlaced ? FieldParity::Top : FieldParity::Progressive};
      (void)mWarper->produce(*frame, mMotion.poseAt(display), spec, scratch);
      w.warpMs = toSeconds(mClock.now() - start) * 1e3;
      w.frameNumber = frame->frameNumber;
    }
  } catch (const std::exception& e) {
    spdlog::warn("field warm-up: {}", e.what());  // not fatal: the first field does the same work
  }
  w.done = mClock.now();
  return w;
}

void Channel::startFields(PlanFields plan, FieldLoop::BeforeField beforeField, PendingInput* pendingInput) {
  warp::FieldClockConfig clockConfig;
  clockConfig.rate = mSettings.output.fieldRate;
  clockConfig.scan = mSettings.output.scan;
  clockConfig.order = mSettings.output.fieldOrder;
  clockConfig.lead = mSettings.prp.lead;
  warp::validateFieldClockConfig(clockConfig, "warp.lead_ms");
  const ThreadsConfig& threads = mSettings.threads;
  mFieldThread = std::thread([this, clockConfig, threads, plan = std::move(plan), beforeField = std::move(beforeField),
                              pendingInput]() mutable {
    spdlog::info("{}", applyScheduling("fc-field",
                                       ThreadScheduling{threads.realtimeFieldThread, 50, -5, threads.fieldThreadCpu}));
    try {
      prefaultStack();
      const WarmUp warm = warmUp();
      const FieldStart start = plan(warm);
      mFieldClock = std::make_unique<warp::FieldClock>(mClock, clockConfig, start.t0, start.firstField);
      mFieldLoop = std::make_unique<FieldLoop>(*mFieldClock, mClock, *mWarper, mFrames, mMotion, *mSinks, mMetrics,
                                               pendingInput);
      if (beforeField) mFieldLoop->setBeforeField(std::move(beforeField));
      mFieldClockReady.store(true, std::memory_order_release);
      mFieldLoop->run(mStopFields, start.end, start.fieldCount);
    } catch (const std::exception& e) {
      mOnFatal(std::string("fields: ") + e.what());
    }
    mFieldsDone.store(true, std::memory_order_release);
  });
  // The caller may use fieldClock() once this returns.
  while (!mFieldClockReady.load(std::memory_order_acquire) && !mFieldsDone.load(std::memory_order_acquire)) {
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  spdlog::info("fields: {}, {} warp, lead {} ms", mSettings.output.describe(), toString(mSettings.prp.warper.warp),
               toSeconds(clockConfig.lead) * 1e3);
}

void Channel::stop() {
  mStopFields.store(true);
  if (mFieldThread.joinable()) mFieldThread.join();
  mStopRender.store(true);
  if (mRenderThread.joinable()) mRenderThread.join();
  if (mSinks && !mSinksStopped) {
    mSinksStopped = true;
    mSinks->stop();  // drains the queues and finalises every output
    spdlog::info("outputs: {}", mSinks->summary());
  }
}

std::string Channel::sinksSummary() const { return mSinks ? mSinks->summary() : std::string(); }

std::uint64_t Channel::sinksDropped() const { return mSinks ? mSinks->droppedTotal() : 0; }

}  // namespace fieldcast::app
