#include "Channel.h"

#include "ThreadScheduling.h"

#include <ig_core/Renderer.h>

#include <spdlog/spdlog.h>

namespace fieldcast::app {

ChannelSettings channelSettingsOf(const ServiceConfig& config) {
  ChannelSettings s;
  s.view.offset = config.view;
  s.view.display =
      Intrinsics::fromHorizontalFov(config.render.widthPx, config.render.heightPx, radians(config.render.hfovDeg));
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
      mClock(clock),
      mMetrics(metrics),
      mOnFatal(std::move(onFatal)) {
  warp::FieldWarperConfig warper = settings.prp.warper;
  warper.rasterWidthPx = settings.output.widthPx;
  warper.rasterHeightPx = settings.output.heightPx;
  warper.outputFormat = settings.output.pixelFormat;
  warper.maxFrameWidthPx = settings.view.display.widthPx * 2;
  warper.maxFrameHeightPx = settings.view.display.heightPx * 2;
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
    RenderLoop loop(renderer, mMotion, mSettings.view.display, mFrames, mMetrics, pacing, &mTerrain);
    spdlog::info("render: {} worker threads, {}x{} display, margin {:.0f}%", renderer.threads(),
                 mSettings.view.display.widthPx, mSettings.view.display.heightPx, render.settings.marginFraction * 100);
    if (!loop.run(mStopRender)) mOnFatal("render thread stopped (see the log above)");
  } catch (const std::exception& e) {
    mOnFatal(std::string("render: ") + e.what());
  }
}

void Channel::startFields(TimePoint t0, std::uint64_t lastField, FieldLoop::BeforeField beforeField,
                          PendingInput* pendingInput) {
  warp::FieldClockConfig clockConfig;
  clockConfig.rate = mSettings.output.fieldRate;
  clockConfig.scan = mSettings.output.scan;
  clockConfig.order = mSettings.output.fieldOrder;
  clockConfig.lead = mSettings.prp.lead;
  warp::validateFieldClockConfig(clockConfig, "warp.lead_ms");
  mFieldClock = std::make_unique<warp::FieldClock>(mClock, clockConfig, t0);
  mFieldLoop =
      std::make_unique<FieldLoop>(*mFieldClock, mClock, *mWarper, mFrames, mMotion, *mSinks, mMetrics, pendingInput);
  if (beforeField) mFieldLoop->setBeforeField(std::move(beforeField));
  const ThreadsConfig& threads = mSettings.threads;
  mFieldThread = std::thread([this, lastField, threads] {
    spdlog::info("{}", applyScheduling("fc-field",
                                       ThreadScheduling{threads.realtimeFieldThread, 50, -5, threads.fieldThreadCpu}));
    mFieldLoop->run(mStopFields, lastField);
    mFieldsDone.store(true, std::memory_order_release);
  });
  spdlog::info("fields: {} from t0, {} warp, lead {} ms", mSettings.output.describe(),
               toString(mSettings.prp.warper.warp), toSeconds(clockConfig.lead) * 1e3);
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
