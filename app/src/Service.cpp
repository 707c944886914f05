#include "Service.h"

#include "FieldLoop.h"
#include "KeyboardFlight.h"
#include "RenderLoop.h"
#include "SinkFactory.h"
#include "ThreadScheduling.h"

#include <ig_core/OpenTerrain.h>
#include <ig_core/Renderer.h>
#include <io_bridge/GpioInput.h>
#include <io_bridge/InputSources.h>
#include <io_bridge/StickInput.h>
#include <io_bridge/StickProfile.h>
#include <motion/FlightModel.h>
#include <motion/ScriptedTrajectory.h>
#include <prp_warp/FieldClock.h>
#include <prp_warp/FieldWarper.h>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace fieldcast::app {
namespace {

using namespace std::chrono_literals;

constexpr auto kFirstFrameTimeout = 60s;  // the first frame also waits for the pinned terrain levels

warp::WarpKind warpKindOf(WarpChoice choice) {
  switch (choice) {
    case WarpChoice::Hold: return warp::WarpKind::Hold;
    case WarpChoice::Quadratic: return warp::WarpKind::Quadratic;
    case WarpChoice::Homography: return warp::WarpKind::Homography;
    case WarpChoice::Range3d: return warp::WarpKind::Range3d;
  }
  return warp::WarpKind::Quadratic;
}

std::unique_ptr<core::TileCache> openTerrainOf(const TerrainConfig& config) {
  core::BuiltinTerrainSpec builtin;
  builtin.sizeVox = config.builtinSizeVoxels;
  builtin.seed = config.builtinSeed;
  const auto budget = static_cast<std::size_t>(config.memoryBudgetMiB) << 20;
  const std::string source = config.source == "builtin" ? "builtin" : config.databasePath.string();
  try {
    return core::openTerrain(source, config.cacheDir, budget, builtin);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("terrain.source: ") + e.what());
  }
}

std::unique_ptr<io::StickInput> openStick(const InputConfig& config, Clock& clock) {
  if (config.stick.empty()) return nullptr;
  io::StickProfile profile = io::StickProfile::generic();
  if (!config.profile.empty()) profile = io::loadStickProfile(config.profile);
  io::StickInputOptions options;
  options.recordPath = config.record;
  options.reconnect = !io::isReplaySpec(config.stick);  // a recording plays once
  io::StickInput::SourceFactory factory;
  try {
    factory = io::makeSourceFactory(config.stick, clock);
    // Open it once now: a stick that is not there is a start-up error, not a silent neutral stick.
    factory();
  } catch (const std::exception& e) {
    throw std::runtime_error("input.stick: " + std::string(e.what()));
  }
  return std::make_unique<io::StickInput>(std::move(factory), std::move(profile), options, clock);
}

}  // namespace

struct Service::Parts {
  ServiceConfig config;
  SystemClock clock;
  ServiceMetrics metrics;
  std::unique_ptr<core::TileCache> terrain;
  std::unique_ptr<motion::ScriptedTrajectory> flight;
  std::unique_ptr<motion::FlightModel> flightModel;
  const motion::MotionSource* motion = nullptr;
  std::unique_ptr<io::StickInput> stick;
  std::unique_ptr<io::GpioInputs> gpio;  // the external field sync, when configured
  std::uint64_t syncPulsesSeen = 0;
  KeyboardFlight keyboard;  // the live window's keys, when there is no stick
  PendingInput pendingInput{0};
  TimePoint lastInputTime{};
  Intrinsics display;
  warp::FrameHandover frames;
  std::unique_ptr<warp::FieldWarper> warper;
  std::unique_ptr<warp::FunctionPoseSource> poses;
  std::unique_ptr<warp::FieldClock> fieldClock;
  std::unique_ptr<io::SinkHub> sinks;
  io::WindowSink* window = nullptr;
  std::unique_ptr<FieldLoop> fieldLoop;
  std::thread renderThread;
  std::thread fieldThread;
  std::atomic<bool> stopRender{false};
  std::atomic<bool> stopFields{false};
  std::atomic<bool> fieldsDone{false};
  std::atomic<bool> started{false};
  bool stopped = false;
  mutable std::mutex fatalMutex;
  std::string fatal;
  ServiceFigures figures;

  void fail(const std::string& why) {
    {
      std::lock_guard lock(fatalMutex);
      if (fatal.empty()) fatal = why;
    }
    stopRender.store(true);
    stopFields.store(true);
  }

  void renderMain() {
    // Render workers inherit this thread's niceness: on a machine with fewer cores than
    // threads, the field thread then wins the CPU whenever a field is due.
    spdlog::info("{}", applyScheduling("fc-render", ThreadScheduling{false, 0, 5, -1}));
    try {
      core::RenderSettings settings;
      settings.quality = config.render.quality;
      settings.maxAnisotropy = config.render.maxAnisotropy;
      settings.marginFraction = config.render.marginFraction;
      settings.rangeImage = config.render.rangeImage || config.warp.kind == WarpChoice::Range3d;
      settings.colourMode = config.render.grey ? core::FrameColour::Grey : core::FrameColour::Rgb;
      core::Renderer renderer(terrain->view(), settings, config.render.threads);
      RenderPacing pacing;
      pacing.maxRateHz = config.render.maxRateHz;
      pacing.controller.target = fromSeconds(config.render.targetFrameMs * 1e-3);
      pacing.initialQuality = config.render.quality;
      // A fixed grazing rule stays on; otherwise the controller may turn it on before `quality`.
      pacing.controller.grazingAnisotropy =
          config.render.maxAnisotropy > 0.0 ? 0.0 : config.render.controllerAnisotropy;
      RenderLoop loop(renderer, *motion, display, frames, metrics, pacing, terrain.get());
      spdlog::info("render: {} worker threads, {}x{} display, margin {:.0f}%", renderer.threads(), display.widthPx,
                   display.heightPx, config.render.marginFraction * 100);
      if (!loop.run(stopRender)) fail("render thread stopped (see the log above)");
    } catch (const std::exception& e) {
      fail(std::string("render: ") + e.what());
    }
  }

  void fieldMain(std::uint64_t lastField) {
    spdlog::info("{}", applyScheduling("fc-field", ThreadScheduling{config.threads.realtimeFieldThread, 50, -5,
                                                                    config.threads.fieldThreadCpu}));
    fieldLoop->run(stopFields, lastField);
    fieldsDone.store(true, std::memory_order_release);
  }

  // Per field: a new external sync pulse, once the estimator is locked, disciplines the clock.
  void applyExternalSync() noexcept {
    const io::SyncEstimate estimate = gpio->sync();
    if (!estimate.locked || estimate.pulses == syncPulsesSeen) return;
    syncPulsesSeen = estimate.pulses;
    fieldClock->externalSync(estimate.lastPulse);
  }

  // Per field, before the pose is asked for: the stick flight model integrates up to the field.
  void stepFlight(const warp::FieldTick& tick) noexcept {
    const TimePoint now = clock.now();
    motion::FlightControls controls;
    TimePoint inputTime{};
    if (stick) {
      const io::ControlState state = stick->controlsAt(now);
      controls = motion::FlightControls{state.roll, state.pitch, state.yaw, state.throttle};
      if (state.health == io::InputHealth::Live) inputTime = state.time;
    } else {
      controls = keyboard.controlsAt(now);
      inputTime = keyboard.lastInputTime();
    }
    if (inputTime != lastInputTime && inputTime != TimePoint{}) {
      lastInputTime = inputTime;
      pendingInput.store(inputTime.time_since_epoch().count(), std::memory_order_release);
    }
    flightModel->step(tick.displayTime, controls);
  }
};

Service::Service(const ServiceConfig& config) : mParts(std::make_unique<Parts>()) {
  Parts& p = *mParts;
  p.config = config;
  p.display =
      Intrinsics::fromHorizontalFov(config.render.widthPx, config.render.heightPx, radians(config.render.hfovDeg));
  const io::StreamFormat format = streamFormatOf(config);

  p.terrain = openTerrainOf(config.terrain);
  const core::TerrainGeometry& g = p.terrain->geometry();
  spdlog::info("terrain: {} — {}x{} voxels at {} m, {} levels", p.terrain->sourceName(), g.widthVox, g.heightVox,
               g.spacingM, g.levels);

  if (config.motion.source == MotionChoice::Flight) {
    try {
      p.flight =
          std::make_unique<motion::ScriptedTrajectory>(motion::ScriptedTrajectory::load(config.motion.flightPath));
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("motion.flight: ") + e.what());
    }
    p.motion = p.flight.get();
  } else {
    const auto& s = config.motion.startPose;
    const Pose start{{s[0], s[1], s[2]}, radians(s[3]), 0.0, 0.0};
    core::TileCache* terrain = p.terrain.get();
    p.flightModel = std::make_unique<motion::FlightModel>(
        motion::FlightModelParams{}, start, config.motion.startSpeedMps, p.clock.now(),
        [terrain](double x, double y) { return terrain->heightAtM(x, y); });
    p.motion = p.flightModel.get();
    p.stick = openStick(config.input, p.clock);
  }

  warp::FieldWarperConfig warperConfig;
  warperConfig.warp = warpKindOf(config.warp.kind);
  warperConfig.rasterWidthPx = config.output.widthPx;
  warperConfig.rasterHeightPx = config.output.heightPx;
  warperConfig.outputFormat = config.output.format;
  warperConfig.flickerFilter = config.warp.flickerFilter;
  warperConfig.autoGain.enabled = config.warp.autoGain;
  warperConfig.maxFrameWidthPx = config.render.widthPx * 2;
  warperConfig.maxFrameHeightPx = config.render.heightPx * 2;
  p.warper = std::make_unique<warp::FieldWarper>(warperConfig);
  p.poses = std::make_unique<warp::FunctionPoseSource>(*p.motion);
  Sinks sinks = makeSinks(config, format, [&p](int, io::WindowKey key) {
    if (key == io::WindowKey::Quit) {
      p.stopFields.store(true);  // the main loop sees running() turn false and stops cleanly
    } else {
      p.keyboard.onKey(key, p.clock.now());
    }
  });
  p.sinks = std::move(sinks.hub);
  p.window = sinks.window;

  if (!config.input.sync.empty()) {
    try {
      p.gpio = std::make_unique<io::GpioInputs>(std::chrono::microseconds(500), config.output.fieldRate);
      p.gpio->addSync(io::openGpiodEdgeLine(io::parseGpioLineSpec(config.input.sync)));
    } catch (const std::exception& e) {
      throw std::runtime_error("input.sync: " + std::string(e.what()));
    }
  }
}

Service::~Service() {
  try {
    stop();
  } catch (const std::exception& e) {
    spdlog::error("stopping the service: {}", e.what());
  }
}

void Service::start() {
  Parts& p = *mParts;
  p.sinks->start();  // opens every output now: an unwritable path fails before anything runs
  if (p.flight) p.flight->setStartTime(p.clock.now());
  if (p.stick) p.stick->start();
  if (p.gpio) p.gpio->start();

  p.renderThread = std::thread([&p] { p.renderMain(); });
  p.started.store(true);
  const TimePoint giveUp = p.clock.now() + kFirstFrameTimeout;
  while (p.metrics.counters.framesRendered.load() == 0) {
    if (!fatalError().empty()) throw std::runtime_error(fatalError());
    if (p.clock.now() > giveUp) throw std::runtime_error("render: no frame within 60 s of start");
    std::this_thread::sleep_for(5ms);
  }

  warp::FieldClockConfig clockConfig;
  clockConfig.rate = p.config.output.fieldRate;
  clockConfig.scan = p.config.output.scan;
  clockConfig.order = p.config.output.fieldOrder;
  clockConfig.lead = fromSeconds(p.config.warp.leadMs * 1e-3);
  warp::validateFieldClockConfig(clockConfig, "warp.lead_ms");
  const TimePoint t0 = p.clock.now() + clockConfig.lead + 2ms;
  p.fieldClock = std::make_unique<warp::FieldClock>(p.clock, clockConfig, t0);
  p.metrics.startAt(p.clock.now());
  p.fieldLoop = std::make_unique<FieldLoop>(*p.fieldClock, p.clock, *p.warper, p.frames, *p.poses, *p.sinks, p.metrics,
                                            p.stick ? &p.pendingInput : nullptr);
  if (p.flightModel || p.gpio) {
    p.fieldLoop->setBeforeField([&p](const warp::FieldTick& tick) {
      if (p.gpio) p.applyExternalSync();
      if (p.flightModel) p.stepFlight(tick);
    });
  }
  std::uint64_t lastField = 0;
  if (p.config.motion.durationS > 0) {
    lastField = static_cast<std::uint64_t>(std::llround(p.config.motion.durationS * clockConfig.rate.hz()));
  }
  p.fieldThread = std::thread([&p, lastField] { p.fieldMain(lastField); });
  spdlog::info("fields: {} from t0, {} warp, lead {} ms", streamFormatOf(p.config).describe(),
               toString(warpKindOf(p.config.warp.kind)), p.config.warp.leadMs);
}

bool Service::running() const noexcept {
  const Parts& p = *mParts;
  return !p.fieldsDone.load(std::memory_order_acquire) && !p.stopFields.load(std::memory_order_acquire);
}

std::string Service::fatalError() const {
  std::lock_guard lock(mParts->fatalMutex);
  return mParts->fatal;
}

std::string Service::intervalLine() {
  Parts& p = *mParts;
  std::string line = p.metrics.intervalLine(p.clock.now());
  if (p.window != nullptr) {
    const ServiceCounters& c = p.metrics.counters;
    io::WindowFigures figures;
    figures.renderHz = p.metrics.lastRenderHz();
    figures.fields = c.fieldsEmitted.load();
    figures.missedFields = c.fieldsMissed.load();
    figures.marginViolations = c.marginViolations.load();
    p.window->setFigures(figures);
  }
  const core::TileCacheStats t = p.terrain->stats();
  line += " | tiles " + std::to_string(t.residentTiles) + " resident, " + std::to_string(t.viewMisses) + " misses";
  return line;
}

ServiceFigures Service::stop() {
  Parts& p = *mParts;
  if (p.stopped) return p.figures;
  p.stopped = true;
  p.stopFields.store(true);
  if (p.fieldThread.joinable()) p.fieldThread.join();
  p.stopRender.store(true);
  if (p.renderThread.joinable()) p.renderThread.join();
  if (p.stick) p.stick->stop();
  if (p.gpio) p.gpio->stop();
  if (p.sinks) {
    p.sinks->stop();  // drains the queues and finalises every output
    spdlog::info("outputs: {}", p.sinks->summary());
  }
  p.figures = p.metrics.figures(p.clock.now());
  if (!p.config.metrics.summaryJson.empty() && p.started.load()) {
    nlohmann::json summary = toJson(p.figures);
    summary["config"] = p.config.sourcePath;
    summary["output"] = streamFormatOf(p.config).describe();
    summary["terrain"] = p.terrain->sourceName();
    summary["sinks_dropped"] = p.sinks ? p.sinks->droppedTotal() : 0;
    summary["fatal_error"] = fatalError();
    const auto& path = p.config.metrics.summaryJson;
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path);
    out << summary.dump(2) << "\n";
    if (!out) throw std::runtime_error("metrics.summary_json: cannot write " + path.string());
  }
  return p.figures;
}

}  // namespace fieldcast::app
