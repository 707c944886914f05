#include <service/Service.h>

#include "Channel.h"
#include "CockpitActions.h"
#include "FieldLoop.h"
#include "HostDatabases.h"
#include "HostSession.h"
#include "KeyboardFlight.h"
#include "MemoryLock.h"
#include "SceneEntities.h"
#include "TerrainCeiling.h"
#include "ThreadScheduling.h"

#include <io_bridge/FieldLockLink.h>
#include <io_bridge/GpioInput.h>
#include <io_bridge/HostLink.h>
#include <io_bridge/InputSources.h>
#include <io_bridge/StickInput.h>
#include <io_bridge/StickProfile.h>
#include <motion/FlightFile.h>
#include <motion/FlightModel.h>
#include <motion/ScriptedTrajectory.h>
#include <prp_warp/FieldClock.h>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace fieldcast::app {
namespace {

using namespace std::chrono_literals;

constexpr auto kFirstFrameTimeout = 60s;  // the first frame also waits for the pinned terrain levels
// From the end of the field thread's warm-up to the first field's wake-up: the thread is already
// running and warm, so this only has to cover the planning itself.
constexpr Nanoseconds kFirstFieldMargin = 2ms;
// A frame lock whose field 0 comes up to this many fields after this channel's own first field
// would is joined at start rather than begun anew (two channels ready at nearly one instant).
constexpr std::int64_t kJoinLaterLockFields = 6;

// The summary is written at the end of the run: a path that cannot be written is found now, not
// after the run. An existing file is opened for appending (left as it is); a new one is created
// and removed again.
void checkSummaryWritable(const std::filesystem::path& path) {
  if (path.empty()) return;
  std::error_code error;
  const bool existed = std::filesystem::exists(path, error);
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), error);
  std::ofstream probe(path, std::ios::app);
  if (!probe) {
    throw std::runtime_error("metrics.summary_json: cannot write " + path.string() + ": " + std::strerror(errno));
  }
  probe.close();
  if (!existed) std::filesystem::remove(path, error);
}

// The host link's figures for the run summary.
nlohmann::json hostSummary(const io::HostLinkCounters& link, const HostSessionFigures& session,
                           const motion::HostMotion::Counters& samples) {
  nlohmann::json rejected;
  for (std::size_t k = 0; k < io::cigi::kRejectReasonCount; ++k) {
    if (link.rejectedByReason[k] != 0) {
      rejected[std::string(io::cigi::toString(static_cast<io::cigi::RejectReason>(k)))] = link.rejectedByReason[k];
    }
  }
  return {{"datagrams_received", link.datagramsReceived},
          {"datagrams_accepted", link.datagramsAccepted},
          {"datagrams_byte_swapped", link.datagramsByteSwapped},
          {"datagrams_rejected", link.datagramsRejected},
          {"rejected_by_reason", rejected},
          {"packets_skipped", link.packetsSkipped},
          {"start_of_frames_sent", link.messagesSent},
          {"fields_before_host", link.fieldsWithoutHost},
          {"fields_coalesced", link.fieldsCoalesced},
          {"send_errors", link.sendErrors},
          {"ownship_samples", samples.accepted},
          {"samples_reordered", samples.reordered},
          {"samples_duplicated", samples.duplicates},
          {"host_restarts", samples.restarts},
          {"samples_invalid", samples.invalid},
          {"hat_hot_requests", session.hatHotRequests},
          {"hat_hot_answered", session.hatHotAnswered},
          {"los_requests", session.losRequests},
          {"los_hits", session.losHits},
          {"periodic_requests", session.periodicRequests},
          {"periodic_answers", session.periodicAnswers},
          {"periodic_refused", session.periodicRefused},
          {"requests_refused", session.requestsRefused},
          {"other_entities", session.otherEntities},
          {"mode_changes", session.modeChanges},
          {"last_host_frame", session.lastHostFrame},
          {"view_controls", session.viewControls},
          {"view_controls_ignored", session.viewControlsIgnored},
          {"view_definitions", session.viewDefinitions},
          {"view_definitions_ignored", session.viewDefinitionsIgnored},
          {"celestial_controls", session.celestialControls},
          {"celestial_refused", session.celestialRefused}};
}

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
  try {
    options.arrivals = io::makeArrivalWatch(config.stick);  // USB hotplug where libusb has it
    if (options.arrivals) spdlog::info("input.stick: reconnects on USB hotplug arrival, polling as the fallback");
  } catch (const std::exception& e) {
    spdlog::warn("input.stick: no USB hotplug ({}); reconnecting by polling", e.what());
  }
  return std::make_unique<io::StickInput>(std::move(factory), std::move(profile), options, clock);
}

// A scripted flight flown from an instant set once the first field's time is known (time 0 is the
// first field's display time, so the video opens on the flight's start). Frames rendered before
// that see the flight's approach. Thread-safe: the start is an atomic.
class FlownFlight final : public motion::MotionSource {
 public:
  explicit FlownFlight(const motion::ScriptedTrajectory& flight) : mFlight(flight) {}
  void setStart(TimePoint start) noexcept {
    mStartNs.store(start.time_since_epoch().count(), std::memory_order_release);
  }
  TimePoint start() const noexcept { return TimePoint{Nanoseconds{mStartNs.load(std::memory_order_acquire)}}; }
  Pose poseAt(TimePoint t) const noexcept override { return mFlight.poseAtSeconds(toSeconds(t - start())); }

 private:
  const motion::ScriptedTrajectory& mFlight;
  std::atomic<std::int64_t> mStartNs{0};
};

}  // namespace

struct Service::Parts {
  ServiceConfig config;
  SystemClock clock;
  ServiceMetrics metrics;
  std::shared_ptr<core::TileCache> terrain;  // null once HostDatabases owns it: see currentTerrain()
  std::unique_ptr<motion::ScriptedTrajectory> flight;
  std::unique_ptr<FlownFlight> flown;
  std::unique_ptr<SceneEntities> entities;  // a flight's scripted entities; null: none
  std::unique_ptr<motion::FlightModel> flightModel;
  // motion.source = "host": the link's thread feeds the session, the session the host motion.
  // Declared in that order so the link stops first.
  std::unique_ptr<motion::HostMotion> hostMotion;
  std::unique_ptr<HostSession> hostSession;
  std::unique_ptr<io::HostLink> hostLink;
  const motion::MotionSource* ownship = nullptr;
  std::unique_ptr<io::StickInput> stick;
  std::unique_ptr<io::GpioInputs> gpio;     // the external field sync and the cockpit discretes, when configured
  std::unique_ptr<CockpitActions> cockpit;  // freeze/reset/trigger: the ownship of a flight or the stick model
  std::uint64_t syncPulsesSeen = 0;
  // [lock]: the software frame lock with the other channels, and the epoch this channel is on
  std::unique_ptr<io::FieldLockLink> lock;
  TimePoint lockEpoch{};
  std::uint64_t lockFirstField = 0;
  KeyboardFlight keyboard;  // the live window's keys, when there is no stick
  PendingInput pendingInput{0};
  TimePoint lastInputTime{};
  std::unique_ptr<Channel> channel;
  // The databases a host may switch between. Declared after the channel: its loader thread asks
  // the channel what it renders, so it is stopped first.
  std::unique_ptr<HostDatabases> hostDatabases;
  std::atomic<bool> started{false};
  bool stopped = false;
  mutable std::mutex fatalMutex;
  std::string fatal;
  std::atomic<bool> failed{false};  // fatal is set: read without the lock
  ServiceFigures figures;

  // The terrain rendered now: a host's database switch replaces the one opened at start.
  std::shared_ptr<core::TileCache> currentTerrain() const {
    return hostDatabases ? hostDatabases->current().terrain : terrain;
  }

  void fail(const std::string& why) {
    {
      std::lock_guard guard(fatalMutex);
      if (fatal.empty()) fatal = why;
    }
    failed.store(true, std::memory_order_release);
    if (channel) channel->requestStop();
  }

  // At the start: join the lock the other channels hold (the earliest epoch heard) at its first
  // field displayed after this channel is ready (interlaced: a frame's first field, even); with
  // none heard, this channel's field 0 is the lock's epoch. A lock that begins a few fields after
  // this channel's own first field would is joined too: two channels ready at nearly one instant
  // then share one lock from their first field instead of one moving onto the other's.
  void joinFrameLock(FieldStart& start, TimePoint& firstTime) {
    const std::optional<TimePoint> heard = lock->earliestEpochHeard();
    const RationalRate rate = config.output.fieldRate;
    if (heard && *heard < start.t0 + rate.tickOffset(kJoinLaterLockFields)) {
      std::uint64_t k = warp::firstFieldAtOrAfter(rate, *heard, start.t0);
      if (config.output.scan == ScanMode::Interlaced) k += k & 1U;
      start.t0 = *heard;
      start.firstField = k;
      firstTime = *heard + rate.tickOffset(static_cast<std::int64_t>(k));
      spdlog::info("frame lock: joined at field {} (the lock's field 0 is {:.3f} s before it)", k,
                   toSeconds(firstTime - *heard));
    } else {
      spdlog::info("frame lock: this channel's field 0 is the lock's epoch ({} announced)",
                   heard ? "a later one was" : "none was yet");
    }
    lockEpoch = start.t0;
    lockFirstField = start.firstField;
    lock->announce(lockEpoch, start.firstField);
  }

  // Per field: a peer's earlier epoch moves this channel onto it (from the next field on), and the
  // flight with it, so every channel shows the flight's same instant in its field k.
  void followFrameLock(const warp::FieldTick& tick) noexcept {
    const std::optional<TimePoint> heard = lock->earliestEpochHeard();
    if (heard && *heard < lockEpoch - io::kSameLockTolerance) {
      lockEpoch = *heard;
      channel->fieldClock()->lockTo(lockEpoch);
      if (flown) flown->setStart(lockEpoch);
    }
    lock->announce(lockEpoch, tick.fieldNumber);
  }

  // Per field: a new external sync pulse, once the estimator is locked, disciplines the clock.
  void applyExternalSync() noexcept {
    if (config.input.sync.empty()) return;
    const io::SyncEstimate estimate = gpio->sync();
    if (!estimate.locked || estimate.pulses == syncPulsesSeen) return;
    syncPulsesSeen = estimate.pulses;
    channel->fieldClock()->externalSync(estimate.lastPulse);
  }

  // Per field, before the pose is asked for: freeze, reset and trigger from the discretes and the
  // stick's mapped buttons, at the field's display time.
  void actOnCockpit(const warp::FieldTick& tick, const io::ControlState* stickState) noexcept {
    io::DiscreteSnapshot discretes;
    if (gpio) discretes = gpio->discretes();
    cockpit->beforeField(tick.displayTime, gpio ? &discretes : nullptr, stickState ? stickState->buttons : 0);
  }

  // Per field, before the pose is asked for: the stick flight model integrates up to the field
  // (in the flight's time, which stands still while the cockpit is frozen).
  void stepFlight(const warp::FieldTick& tick, TimePoint now, const io::ControlState* stickState) noexcept {
    motion::FlightControls controls;
    TimePoint inputTime{};
    if (stickState) {
      const io::ControlState& state = *stickState;
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
    flightModel->step(cockpit->flightTime(tick.displayTime), controls);
  }
};

Service::Service(const ServiceConfig& config) : mParts(std::make_unique<Parts>()) {
  Parts& p = *mParts;
  p.config = config;
  checkSummaryWritable(config.metrics.summaryJson);
  if (!config.metrics.fieldLog.empty()) p.metrics.openFieldLog(config.metrics.fieldLog);  // checks the path now

  p.terrain = core::openTerrain(config.terrain);
  const core::TerrainGeometry& g = p.terrain->geometry();
  spdlog::info("terrain: {} — {}x{} voxels at {} m, {} levels", p.terrain->sourceName(), g.widthVox, g.heightVox,
               g.spacingM, g.levels);
  // The haze range: configured, or from the database's extent so a large one is not a wall of haze.
  double& visibility = p.config.render.settings.hazeRangeM;
  if (!config.render.visibilityGiven)
    visibility = core::defaultVisibilityM(std::max(g.widthVox, g.heightVox) * g.spacingM);
  spdlog::info("haze: visibility {:.0f} m ({})", visibility,
               config.render.visibilityGiven ? "render.visibility_m" : "from the database's extent");
  p.metrics.setVisibility(visibility);

  std::shared_ptr<const core::Georeference> georeference;  // motion.source = "host": where the database lies
  std::vector<motion::ScriptedEntity> scriptedEntities;    // motion.source = "flight": its [[entity]] tables
  if (config.motion.source == motion::MotionKind::Flight) {
    try {
      motion::FlightFile file = motion::readFlightFile(config.motion.flightPath);
      p.flight = std::make_unique<motion::ScriptedTrajectory>(std::move(file.ownship));
      scriptedEntities = std::move(file.entities);
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("motion.flight: ") + e.what());
    }
    // Never below the terrain: the bound of the pinned levels, which neither misses a tile nor
    // changes as tiles load, so the lift over a hill is smooth and the same every run.
    const core::TerrainView* view = &p.terrain->view();
    const int level = p.terrain->stats().pinnedFromLevel;
    p.flight->setTerrainFloor([view, level](double x, double y) { return terrainCeilingM(*view, level, x, y); });
    p.flown = std::make_unique<FlownFlight>(*p.flight);
    if (!scriptedEntities.empty()) {
      p.entities = std::make_unique<SceneEntities>(
          scriptedEntities, view, [flown = p.flown.get()](TimePoint t) { return toSeconds(t - flown->start()); });
      spdlog::info("entities: {} scripted by the flight", p.entities->size());
    }
    // Reset: time 0 of the flight is now.
    p.cockpit = std::make_unique<CockpitActions>(*p.flown, io::CockpitButtons{},
                                                 [flown = p.flown.get()](TimePoint now) { flown->setStart(now); });
    p.ownship = p.cockpit.get();
  } else if (config.motion.source == motion::MotionKind::Host) {
    p.hostMotion = std::make_unique<motion::HostMotion>(config.host.motion, config.motion.start);
    p.ownship = p.hostMotion.get();
    p.metrics.setHostSamples(p.hostMotion.get());  // the field record's host columns, host→field latency
    try {
      georeference = std::make_shared<const core::Georeference>(
          core::Georeference::forTerrain(p.terrain->crs(), config.host.origin));
      spdlog::info("host: CIGI 3.3 on {}:{}, positions through the {}", config.host.link.listenAddress,
                   config.host.link.port, georeference->description());
      p.hostSession =
          std::make_unique<HostSession>(*p.hostMotion, *p.terrain, georeference, config.host.databaseNumber, p.clock);
      io::HostLinkConfig link = config.host.link;
      // Start of Frame and the answers are due every field: the link's thread runs just below the
      // field thread, so a busy machine cannot hold it off for fields at a time.
      link.onThreadStart = [realtime = config.threads.realtimeHostThread] {
        spdlog::info("{}", applyScheduling("fc-host-link", ThreadScheduling{realtime, 45, -5, -1}));
      };
      p.hostLink = std::make_unique<io::HostLink>(link, p.clock, *p.hostSession);
      if (!config.host.entityModels.empty()) {
        p.entities = std::make_unique<SceneEntities>(std::vector<motion::ScriptedEntity>{}, nullptr,
                                                     [](TimePoint) { return 0.0; });
        p.entities->setHost(
            [session = p.hostSession.get()](std::vector<HostEntitySample>& out) { session->copyEntities(out); },
            config.host.entityModels,
            [ownship = p.hostMotion.get()](TimePoint t) { return ownship->poseAt(t); });  // its attachments
        spdlog::info("host: entities of {} types drawn", config.host.entityModels.size());
        p.hostSession->setEntityScene(
            [entities = p.entities.get()](TimePoint t, std::vector<core::EntityInstance>& out) {
              entities->at(t, out);
            });
      }
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("host: ") + e.what());
    }
  } else {
    core::TileCache* terrain = p.terrain.get();
    p.flightModel = std::make_unique<motion::FlightModel>(
        motion::FlightModelParams{}, config.motion.start, config.motion.startSpeedMps, p.clock.now(),
        [terrain](double x, double y) { return terrain->heightAtM(x, y); });
    p.stick = openStick(config.input, p.clock);
    // Reset: the start pose and speed, now.
    p.cockpit = std::make_unique<CockpitActions>(
        *p.flightModel, p.stick ? p.stick->profile().cockpit : io::CockpitButtons{},
        [model = p.flightModel.get(), start = config.motion.start, speed = config.motion.startSpeedMps](TimePoint now) {
          model->reset(start, speed, now);
        });
    p.ownship = p.cockpit.get();
  }

  if (!config.lock.listen.empty()) {
    p.lock = std::make_unique<io::FieldLockLink>(config.lock, config.output.fieldRate, p.clock);
    spdlog::info("frame lock: listening on {}, announcing to {} other channels", config.lock.listen,
                 config.lock.peers.size());
  }
  p.channel = std::make_unique<Channel>(
      channelSettingsOf(p.config), *p.terrain, *p.ownship, p.clock, p.metrics,
      [&p](const std::string& why) { p.fail(why); },
      [&p](int, io::WindowKey key) {
        if (key == io::WindowKey::Quit) {
          p.channel->requestStop();  // the main loop sees running() turn false and stops cleanly
        } else {
          p.keyboard.onKey(key, p.clock.now());
        }
      });

  if (p.hostSession && !config.host.databases.empty()) {
    OpenDatabase first{config.host.databaseNumber, std::move(p.terrain), std::move(georeference)};
    p.hostDatabases = std::make_unique<HostDatabases>(
        std::move(first), config.host.databases, config.host.origin, [&p] { return p.channel->terrainSettled(); },
        [&p](core::TileCache& terrain) { p.channel->switchTerrain(terrain); });
    p.hostSession->setDatabases(p.hostDatabases.get());
  }
  if (p.hostSession) {
    p.hostSession->setUtcOffset(config.host.celestialUtcOffsetH);
    // View Control moves the head: a stereo eye keeps its place beside it
    p.hostSession->setView(HostView{
        config.host.viewId, config.host.viewGroup, config.view.offset,
        [&p, view = config.view](const ViewOffset& head) { p.channel->setViewOffset(eyeOffset(head, view)); },
        p.channel->settings().view.display, [&p](const Intrinsics& display) { p.channel->setDisplay(display); },
        [&p](warp::Mirror mirror) { p.channel->setMirror(mirror); }});
  }

  const std::pair<const char*, const std::string*> gpioLines[] = {{"sync", &config.input.sync},
                                                                  {"freeze", &config.input.freeze},
                                                                  {"reset", &config.input.reset},
                                                                  {"trigger", &config.input.trigger}};
  for (const auto& [key, spec] : gpioLines) {
    if (spec->empty()) continue;
    try {
      if (!p.gpio) p.gpio = std::make_unique<io::GpioInputs>(std::chrono::microseconds(500), config.output.fieldRate);
      auto line = io::openGpiodEdgeLine(io::parseGpioLineSpec(*spec));
      const std::string_view k(key);
      if (k == "sync") {
        p.gpio->addSync(std::move(line));
      } else {
        p.gpio->addDiscrete(k == "freeze"  ? io::Discrete::Freeze
                            : k == "reset" ? io::Discrete::Reset
                                           : io::Discrete::Trigger,
                            std::move(line));
      }
    } catch (const std::exception& e) {
      throw std::runtime_error("input." + std::string(key) + ": " + std::string(e.what()));
    }
  }
  if (p.gpio && !p.cockpit &&
      (!config.input.freeze.empty() || !config.input.reset.empty() || !config.input.trigger.empty())) {
    spdlog::warn("input: the cockpit discretes act on a scripted flight or the stick flight, not on the host's motion");
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
  const TimePoint begin = p.clock.now();
  const MemoryLockResult memory = lockMemory();
  if (memory.locked) {
    spdlog::info("{}", memory.report);
  } else {
    spdlog::warn("{}", memory.report);
  }
  p.channel->startOutputs();  // opens every output now: an unwritable path fails before anything runs
  if (p.flown) p.flown->setStart(p.clock.now());  // until the first field's time is known
  if (p.stick) p.stick->start();
  if (p.gpio) p.gpio->start();
  if (p.lock) {
    // Hear the other channels before the first frame: a channel joining a running lock renders
    // its flight at the lock's time from the start
    p.lock->start();
    p.lock->awaitPeers();
    if (const std::optional<TimePoint> heard = p.lock->earliestEpochHeard(); heard && p.flown)
      p.flown->setStart(*heard);
  }
  if (p.hostLink) p.hostLink->start();

  if (p.hostSession) {
    p.channel->setHazeRange(&p.hostSession->hazeRangeM());  // the host's visibility
    p.channel->setSun(&p.hostSession->sun());               // and time of day
  }
  if (p.entities) p.channel->setEntities(p.entities.get());
  p.channel->startRendering();
  p.started.store(true);
  const TimePoint giveUp = p.clock.now() + kFirstFrameTimeout;
  while (p.metrics.counters.framesRendered.load() == 0) {
    if (!fatalError().empty()) throw std::runtime_error(fatalError());
    if (p.clock.now() > giveUp) throw std::runtime_error("render: no frame within 60 s of start");
    std::this_thread::sleep_for(5ms);
  }

  FieldLoop::BeforeField beforeField;
  if (p.flightModel || p.gpio || p.hostLink || p.cockpit || p.lock) {
    beforeField = [&p](const warp::FieldTick& tick) {
      // The stick is read once per field: the cockpit's buttons and the flight model see one state.
      const TimePoint now = p.clock.now();
      io::ControlState stickState;
      if (p.stick) stickState = p.stick->controlsAt(now);
      const io::ControlState* stick = p.stick ? &stickState : nullptr;
      if (p.gpio) p.applyExternalSync();
      if (p.lock) p.followFrameLock(tick);
      if (p.cockpit) p.actOnCockpit(tick, stick);
      if (p.hostLink) p.hostLink->fieldStarted(tick.fieldNumber, tick.displayTime, tick.renumbered);  // Start of Frame
      if (p.flightModel) p.stepFlight(tick, now, stick);
    };
  }
  // Runs on the field thread once it is warm: the first deadline comes after the warm-up.
  auto plan = [&p, begin, memory = memory.locked](const WarmUp& warm) {
    const RationalRate rate = p.config.output.fieldRate;
    FieldStart start;
    start.t0 = std::max(warm.done, p.clock.now()) + p.config.warp.lead + kFirstFieldMargin;
    TimePoint firstTime = start.t0;
    if (p.lock) p.joinFrameLock(start, firstTime);
    const auto fieldAt = [&](std::uint64_t k) { return start.t0 + rate.tickOffset(static_cast<std::int64_t>(k)); };
    // --duration: that many fields of the schedule, emitted or missed (a genlocked clock's period
    // is not quite the nominal one, and a move onto another lock renumbers the fields)
    if (p.config.motion.durationS > 0)
      start.fieldCount = static_cast<std::uint64_t>(std::llround(p.config.motion.durationS * rate.hz()));
    // The flight starts at field 0: with a frame lock, every channel flies the same instant in
    // its field k. Its end is an instant: a channel that moves onto an earlier lock later (and
    // its flight with it) still ends at this one, showing the flight's last pose until then.
    if (p.flown) p.flown->setStart(start.t0);
    if (p.flight && p.flight->end() == motion::FlightEnd::Stop) {
      // The fields displayed up to the flight's end, the last one included
      const std::uint64_t flightFields =
          warp::firstFieldAtOrAfter(rate, start.t0, start.t0 + fromSeconds(p.flight->durationS()) + Nanoseconds{1});
      start.end = std::min(start.end, fieldAt(flightFields));
    }
    StartupFigures s;
    s.toFirstFieldS = toSeconds(firstTime - p.config.warp.lead - begin);
    s.warmUpWarpMs = warm.warpMs;
    s.warmUpFrame = warm.frameNumber;
    s.memoryLocked = memory;
    s.tileMisses = p.currentTerrain()->stats().viewMisses;
    p.metrics.setStartup(s);
    p.metrics.startAt(warm.done);
    spdlog::info("start-up: {:.2f} s to the first field, warm-up warp {:.2f} ms (frame {}), {} tile misses so far",
                 s.toFirstFieldS, s.warmUpWarpMs, s.warmUpFrame, s.tileMisses);
    return start;
  };
  p.channel->startFields(std::move(plan), std::move(beforeField), p.stick ? &p.pendingInput : nullptr);
  if (!fatalError().empty()) throw std::runtime_error(fatalError());
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
  // Misses of this interval only: the start-up's (before the first field) are in the summary.
  const core::TileCacheStats t = p.currentTerrain()->stats();
  line += " | tiles " + std::to_string(t.residentTiles) + " resident, " +
          std::to_string(p.metrics.tileMissesSince(t.viewMisses)) + " misses";
  return line;
}

ServiceFigures Service::stop() {
  Parts& p = *mParts;
  if (p.stopped) return p.figures;
  p.stopped = true;
  p.channel->stop();  // fields, then rendering, then the outputs are finalised
  if (p.stick) p.stick->stop();
  if (p.gpio) p.gpio->stop();
  if (p.lock) p.lock->stop();
  if (p.hostLink) p.hostLink->stop();
  if (p.started.load()) (void)p.metrics.tileMissesSince(p.currentTerrain()->stats().viewMisses);
  p.metrics.closeFieldLog();  // the fields have stopped: its last records are written
  p.figures = p.metrics.figures(p.clock.now());
  if (!p.config.metrics.summaryJson.empty() && p.started.load()) {
    nlohmann::json summary = toJson(p.figures);
    summary["config"] = p.config.sourcePath;
    summary["output"] = p.config.output.describe();
    summary["terrain"] = p.currentTerrain()->sourceName();
    summary["sinks_dropped"] = p.channel->sinksDropped();
    summary["fatal_error"] = fatalError();
    if (p.cockpit) {
      const CockpitFigures c = p.cockpit->figures();
      summary["cockpit"] = {{"freezes", c.freezes}, {"resets", c.resets}, {"triggers", c.triggers}};
    }
    if (p.lock) {
      const io::FieldLockCounters c = p.lock->counters();
      const warp::FieldClock* clock = p.channel->fieldClock();
      summary["lock"] = {{"epoch_ns", p.lockEpoch.time_since_epoch().count()},
                         {"first_field", p.lockFirstField},
                         {"relocks", clock ? clock->relocks() : 0},
                         {"announcements_sent", c.sent},
                         {"announcements_heard", c.received},
                         {"other_rate", c.otherRate},
                         {"malformed", c.malformed},
                         {"strangers", c.strangers},
                         {"send_errors", c.sendErrors}};
    }
    if (p.hostLink)
      summary["host"] = hostSummary(p.hostLink->counters(), p.hostSession->figures(), p.hostMotion->counters());
    if (p.hostDatabases) {
      summary["host"]["database_number"] = p.hostDatabases->current().number;
      summary["host"]["database_switches"] = p.hostDatabases->switches();
      summary["host"]["database_load_failures"] = p.hostDatabases->failures();
    }
    const auto& path = p.config.metrics.summaryJson;
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path);
    out << summary.dump(2) << "\n";
    if (!out) throw std::runtime_error("metrics.summary_json: cannot write " + path.string());
  }
  return p.figures;
}

}  // namespace fieldcast::app
