#include <service/Service.h>

#include "Channel.h"
#include "FieldLoop.h"
#include "KeyboardFlight.h"

#include <io_bridge/GpioInput.h>
#include <io_bridge/InputSources.h>
#include <io_bridge/StickInput.h>
#include <io_bridge/StickProfile.h>
#include <motion/FlightModel.h>
#include <motion/ScriptedTrajectory.h>
#include <prp_warp/FieldClock.h>

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

std::unique_ptr<io::StickInput> openStick(const io::InputConfig& config, Clock& clock) {
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
  const motion::MotionSource* ownship = nullptr;
  std::unique_ptr<io::StickInput> stick;
  std::unique_ptr<io::GpioInputs> gpio;  // the external field sync, when configured
  std::uint64_t syncPulsesSeen = 0;
  KeyboardFlight keyboard;  // the live window's keys, when there is no stick
  PendingInput pendingInput{0};
  TimePoint lastInputTime{};
  std::unique_ptr<Channel> channel;
  std::atomic<bool> started{false};
  bool stopped = false;
  mutable std::mutex fatalMutex;
  std::string fatal;
  std::atomic<bool> failed{false};  // fatal is set: read without the lock
  ServiceFigures figures;

  void fail(const std::string& why) {
    {
      std::lock_guard lock(fatalMutex);
      if (fatal.empty()) fatal = why;
    }
    failed.store(true, std::memory_order_release);
    if (channel) channel->requestStop();
  }

  // Per field: a new external sync pulse, once the estimator is locked, disciplines the clock.
  void applyExternalSync() noexcept {
    const io::SyncEstimate estimate = gpio->sync();
    if (!estimate.locked || estimate.pulses == syncPulsesSeen) return;
    syncPulsesSeen = estimate.pulses;
    channel->fieldClock()->externalSync(estimate.lastPulse);
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

  p.terrain = core::openTerrain(config.terrain);
  const core::TerrainGeometry& g = p.terrain->geometry();
  spdlog::info("terrain: {} — {}x{} voxels at {} m, {} levels", p.terrain->sourceName(), g.widthVox, g.heightVox,
               g.spacingM, g.levels);

  if (config.motion.source == motion::MotionKind::Flight) {
    try {
      p.flight =
          std::make_unique<motion::ScriptedTrajectory>(motion::ScriptedTrajectory::load(config.motion.flightPath));
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("motion.flight: ") + e.what());
    }
    p.ownship = p.flight.get();
  } else {
    core::TileCache* terrain = p.terrain.get();
    p.flightModel = std::make_unique<motion::FlightModel>(
        motion::FlightModelParams{}, config.motion.start, config.motion.startSpeedMps, p.clock.now(),
        [terrain](double x, double y) { return terrain->heightAtM(x, y); });
    p.ownship = p.flightModel.get();
    p.stick = openStick(config.input, p.clock);
  }

  p.channel = std::make_unique<Channel>(
      channelSettingsOf(config), *p.terrain, *p.ownship, p.clock, p.metrics,
      [&p](const std::string& why) { p.fail(why); },
      [&p](int, io::WindowKey key) {
        if (key == io::WindowKey::Quit) {
          p.channel->requestStop();  // the main loop sees running() turn false and stops cleanly
        } else {
          p.keyboard.onKey(key, p.clock.now());
        }
      });

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
  p.channel->startOutputs();  // opens every output now: an unwritable path fails before anything runs
  if (p.flight) p.flight->setStartTime(p.clock.now());
  if (p.stick) p.stick->start();
  if (p.gpio) p.gpio->start();

  p.channel->startRendering();
  p.started.store(true);
  const TimePoint giveUp = p.clock.now() + kFirstFrameTimeout;
  while (p.metrics.counters.framesRendered.load() == 0) {
    if (!fatalError().empty()) throw std::runtime_error(fatalError());
    if (p.clock.now() > giveUp) throw std::runtime_error("render: no frame within 60 s of start");
    std::this_thread::sleep_for(5ms);
  }

  const TimePoint t0 = p.clock.now() + p.config.warp.lead + 2ms;
  p.metrics.startAt(p.clock.now());
  FieldLoop::BeforeField beforeField;
  if (p.flightModel || p.gpio) {
    beforeField = [&p](const warp::FieldTick& tick) {
      if (p.gpio) p.applyExternalSync();
      if (p.flightModel) p.stepFlight(tick);
    };
  }
  std::uint64_t lastField = 0;
  if (p.config.motion.durationS > 0) {
    lastField = static_cast<std::uint64_t>(std::llround(p.config.motion.durationS * p.config.output.fieldRate.hz()));
  }
  p.channel->startFields(t0, lastField, std::move(beforeField), p.stick ? &p.pendingInput : nullptr);
}

bool Service::running() const noexcept {
  const Parts& p = *mParts;
  return p.channel->fieldsRunning() && !p.failed.load(std::memory_order_acquire);
}

std::string Service::fatalError() const {
  std::lock_guard lock(mParts->fatalMutex);
  return mParts->fatal;
}

std::string Service::intervalLine() {
  Parts& p = *mParts;
  std::string line = p.metrics.intervalLine(p.clock.now());
  if (io::WindowSink* window = p.channel->window()) {
    const ServiceCounters& c = p.metrics.counters;
    io::WindowFigures figures;
    figures.renderHz = p.metrics.lastRenderHz();
    figures.fields = c.fieldsEmitted.load();
    figures.missedFields = c.fieldsMissed.load();
    figures.marginViolations = c.marginViolations.load();
    window->setFigures(figures);
  }
  const core::TileCacheStats t = p.terrain->stats();
  line += " | tiles " + std::to_string(t.residentTiles) + " resident, " + std::to_string(t.viewMisses) + " misses";
  return line;
}

ServiceFigures Service::stop() {
  Parts& p = *mParts;
  if (p.stopped) return p.figures;
  p.stopped = true;
  p.channel->stop();  // fields, then rendering, then the outputs are finalised
  if (p.stick) p.stick->stop();
  if (p.gpio) p.gpio->stop();
  p.figures = p.metrics.figures(p.clock.now());
  if (!p.config.metrics.summaryJson.empty() && p.started.load()) {
    nlohmann::json summary = toJson(p.figures);
    summary["config"] = p.config.sourcePath;
    summary["output"] = p.config.output.describe();
    summary["terrain"] = p.terrain->sourceName();
    summary["sinks_dropped"] = p.channel->sinksDropped();
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
