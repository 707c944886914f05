#include "HostSession.h"

#include <fieldcast/Conventions.h>
#include <ig_core/LineOfSight.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fieldcast::app {
namespace {

namespace cigi = io::cigi;

constexpr double kSecondsPerTick = 10e-6;  // CIGI timestamps count 10 µs ticks
// How long a height answer waits for the full-resolution tiles under it before the best resident
// level answers: the loader reads a tile in about a millisecond, so this is only for a busy disk.
constexpr Nanoseconds kHeightWait = std::chrono::milliseconds(100);
// Periodic requests kept per kind (HAT/HOT, LOS): each costs a query every n-th field on the
// link's thread, so a host cannot make that unbounded.
constexpr std::size_t kMaxPeriodicRequests = 256;
// The longest line of sight measured: 10,000 km, past any database's far side
constexpr double kLongestLineOfSightM = 1e7;
// HAT/HOT (or LOS) requests waiting for their tiles or for room in a Start of Frame message, at
// most: a field's datagram carries some 4,000 answers, so a host asking more than about twice
// that a field is refused the excess (counted) rather than growing the queue and every answer's
// delay without end
constexpr std::size_t kMaxAnswersQueued = 8192;

// The terrain surface the renderer draws at full resolution: bilinear between level-0 voxel centres.
double heightOfTerrain(const core::TileCache& terrain, double x, double y) { return terrain.heightAtM(x, y, 0); }

bool insideDatabase(const core::TerrainGeometry& g, double x, double y) {
  return x >= g.originM.x && y >= g.originM.y && x <= g.originM.x + g.spacingM * (g.widthVox - 1) &&
         y <= g.originM.y + g.spacingM * (g.heightVox - 1);
}

// A world position `offset` (CIGI body axes: x forward, y right, z down, metres) from `pose`.
glm::dvec3 bodyOffset(const Pose& pose, double x, double y, double z) {
  const CameraAxes axes = cameraAxes(pose);
  return pose.positionM + axes.forward * x + axes.right * y - axes.up * z;
}

// An entity's Rate Control as world velocity and heading, pitch and roll rates
void applyRates(const cigi::RateControl& rates, const Pose& pose, glm::dvec3& velocityMps, glm::dvec3& angularRadS) {
  if (rates.frame == cigi::RateFrame::World) {
    // CIGI's world rates are north, east, down; ours are east, north, up.
    velocityMps = {rates.yRateMps, rates.xRateMps, -rates.zRateMps};
  } else {
    velocityMps = bodyOffset(pose, rates.xRateMps, rates.yRateMps, rates.zRateMps) - pose.positionM;
  }
  angularRadS = {radians(rates.yawRateDegps), radians(rates.pitchRateDegps), radians(rates.rollRateDegps)};
}

// CIGI's angles of a unit surface normal: azimuth clockwise from north, elevation above the horizontal.
void normalAngles(const glm::dvec3& normal, float& azimuthDeg, float& elevationDeg) {
  azimuthDeg = static_cast<float>(degrees(std::atan2(normal.x, normal.y)));
  elevationDeg = static_cast<float>(degrees(std::asin(normal.z)));
}

// Appends the answers of `due` to `out` while they fit, and drops those appended from `due`.
template <class Response>
void addWhatFits(cigi::IgMessageBuilder& out, std::vector<Response>& due) {
  std::size_t added = 0;
  while (added < due.size() && out.add(due[added])) ++added;
  due.erase(due.begin(), due.begin() + static_cast<std::ptrdiff_t>(added));
}

}  // namespace

HostSession::HostSession(motion::HostMotion& ownship, core::TileCache& terrain,
                         std::shared_ptr<const core::Georeference> georeference, std::int8_t databaseNumber,
                         const Clock& clock)
    : mOwnship(ownship),
      mTerrain(&terrain),
      mGeoreference(std::move(georeference)),
      mDatabaseNumber(databaseNumber),
      mClock(clock) {}

double HostSession::unwrapHostTime(std::uint32_t ticks) {
  if (!mHaveTime) {
    mHaveTime = true;
    mHostTimeS = ticks * kSecondsPerTick;
  } else {
    // The signed difference: wraps (every 11.9 h) go forward, a reordered datagram a little back.
    const auto step = static_cast<std::int32_t>(ticks - mLastTicks);
    mHostTimeS += step * kSecondsPerTick;
  }
  mLastTicks = ticks;
  return mHostTimeS;
}

void HostSession::onMessage(const io::HostMessage& message) {
  const auto& control = std::get<cigi::IgControl>(message.packets.front());
  if (control.igMode != mMode.load(std::memory_order_relaxed)) {
    constexpr const char* kModes[] = {"reset/standby", "operate", "debug", "offline maintenance"};
    spdlog::info("host: IG mode {} commanded", kModes[static_cast<int>(control.igMode) & 3]);
    mMode.store(control.igMode, std::memory_order_relaxed);
    mModeChanges.fetch_add(1, std::memory_order_relaxed);
    if (control.igMode == cigi::IgMode::ResetStandby) {
      mEntities.clear();  // a reset forgets the scene's entities; the ownship holds its last pose
      mEntitySamples.clear();
      publishEntities();
      mOtherEntities.store(0, std::memory_order_relaxed);
      mPeriodicHeights.clear();  // and the host's periodic requests
      mPeriodicLos.clear();
      mPeriodicRequests.store(0, std::memory_order_relaxed);
    }
  }
  if (control.extrapolationEnabled != mSmoothing) {
    mSmoothing = control.extrapolationEnabled;
    spdlog::info("host: extrapolation/interpolation {}", mSmoothing ? "enabled: the ownship's pose is predicted"
                                                                    : "disabled: the ownship is shown as last sent");
  }
  mLastHostFrame.store(control.hostFrameNumber, std::memory_order_relaxed);
  if (mDatabases != nullptr) mDatabases->request(control.databaseNumber);
  // Without a valid host timestamp the arrival time stands in for it (jitter then reaches the pose).
  const double hostTimeS = control.timestampValid
                               ? unwrapHostTime(control.timestampTicks)
                               : std::chrono::duration<double>(message.arrival.time_since_epoch()).count();
  // Debug is operate with the IG's diagnostics (CIGI 3.3): the scene follows the host in both
  const bool operate = control.igMode == cigi::IgMode::Operate || control.igMode == cigi::IgMode::Debug;

  // The ownship's Entity Control and Rate Control may come in either order: collect, then apply.
  // Requests are answered after both, so that one relative to an entity sees the message's update.
  const cigi::EntityControl* ownship = nullptr;
  const cigi::RateControl* ownshipRates = nullptr;
  std::vector<const cigi::RateControl*> otherRates;
  bool entitiesChanged = false;  // the render loop's copy is made again only then
  std::vector<const cigi::HostPacket*> requests;
  for (const cigi::HostPacket& packet : message.packets) {
    if (const auto* entity = std::get_if<cigi::EntityControl>(&packet)) {
      if (!operate) continue;  // CIGI: entity updates are ignored outside operate mode
      if (entity->entityId == 0) {
        ownship = entity;
      } else if (entity->entityState == cigi::EntityState::Active) {
        mEntities[entity->entityId] = *entity;
        updateEntitySample(*entity, message.arrival);
        entitiesChanged = true;
      } else {
        mEntities.erase(entity->entityId);
        entitiesChanged |= mEntitySamples.erase(entity->entityId) > 0;
      }
    } else if (const auto* rates = std::get_if<cigi::RateControl>(&packet)) {
      if (rates->applyToArticulatedPart) continue;
      if (rates->entityId == 0) {
        ownshipRates = rates;
      } else if (operate) {
        otherRates.push_back(rates);
      }
    } else if (std::holds_alternative<cigi::HatHotRequest>(packet) ||
               std::holds_alternative<cigi::LosSegmentRequest>(packet) ||
               std::holds_alternative<cigi::LosVectorRequest>(packet)) {
      requests.push_back(&packet);
    } else if (const auto* atmosphere = std::get_if<cigi::AtmosphereControl>(&packet)) {
      // Not an entity update: applies in every mode. CIGI's 0 is no visibility, the renderer's 0
      // no haze: hence the 1 m floor.
      if (std::isfinite(atmosphere->visibilityRangeM) && atmosphere->visibilityRangeM >= 0.0f) {
        mHazeRangeM.store(std::max(1.0, hazeRangeForVisibility(atmosphere->visibilityRangeM)),
                          std::memory_order_relaxed);
      }
    } else if (const auto* celestial = std::get_if<cigi::CelestialSphereControl>(&packet)) {
      // Not an entity update either: applies in every mode.
      if (mCelestial.apply(*celestial, message.arrival) == CelestialClock::Applied::Refused) {
        mCelestialRefused.fetch_add(1, std::memory_order_relaxed);
      } else {
        mCelestialControls.fetch_add(1, std::memory_order_relaxed);
        publishSun(message.arrival);
      }
    } else if (const auto* view = std::get_if<cigi::ViewControl>(&packet)) {
      if (operate) applyViewControl(*view);  // a view update: ignored outside operate, as entity updates are
    } else if (const auto* definition = std::get_if<cigi::ViewDefinition>(&packet)) {
      if (operate) applyViewDefinition(*definition);
    }
  }
  mOtherEntities.store(mEntities.size(), std::memory_order_relaxed);
  for (const cigi::RateControl* rates : otherRates) {
    const auto it = mEntitySamples.find(rates->entityId);
    const bool finite = std::isfinite(rates->xRateMps) && std::isfinite(rates->yRateMps) &&
                        std::isfinite(rates->zRateMps) && std::isfinite(rates->rollRateDegps) &&
                        std::isfinite(rates->pitchRateDegps) && std::isfinite(rates->yawRateDegps);
    // Rates that are not numbers are not applied; an attached entity moves with its parent.
    if (it == mEntitySamples.end() || !finite || it->second.attached) continue;
    // New rates from now on: the entity goes on from where its old ones have taken it
    HostEntitySample& sample = it->second;
    sample.pose = extrapolateEntity(sample, message.arrival);
    sample.at = message.arrival;
    applyRates(*rates, sample.pose, sample.velocityMps, sample.angularRateRadS);
    entitiesChanged = true;
  }
  if (entitiesChanged) publishEntities();
  if (ownship != nullptr) applyOwnship(*ownship, ownshipRates, hostTimeS, message.arrival, control.hostFrameNumber);
  // A request refused for the backlog (refusedAsBacklog) is not answered and does not start a
  // periodic request; one that ends or changes a periodic request already kept still does
  const auto heightsWaiting = [this] { return mHeightsWaiting.size() + mHatHotDue.size() + mHatHotExtendedDue.size(); };
  const auto losWaiting = [this] { return mLosWaiting.size() + mLosDue.size() + mLosExtendedDue.size(); };
  for (const cigi::HostPacket* packet : requests) {
    if (const auto* request = std::get_if<cigi::HatHotRequest>(packet)) {
      mHatHotRequests.fetch_add(1, std::memory_order_relaxed);
      const bool answered = !refusedAsBacklog(heightsWaiting());
      if (answered || request->updatePeriod == 0 || mPeriodicHeights.contains(request->hatHotId))
        track(mPeriodicHeights, request->hatHotId, *request, request->updatePeriod);
      if (answered) answer(*request, message.arrival);
    } else if (const auto* segment = std::get_if<cigi::LosSegmentRequest>(packet)) {
      mLosRequests.fetch_add(1, std::memory_order_relaxed);
      const bool answered = !refusedAsBacklog(losWaiting());
      if (answered || segment->updatePeriod == 0 || mPeriodicLos.contains(segment->losId))
        track(mPeriodicLos, segment->losId, LosRequest{*segment}, segment->updatePeriod);
      if (answered) answer(*segment, message.arrival);
    } else if (const auto* vector = std::get_if<cigi::LosVectorRequest>(packet)) {
      mLosRequests.fetch_add(1, std::memory_order_relaxed);
      const bool answered = !refusedAsBacklog(losWaiting());
      if (answered || vector->updatePeriod == 0 || mPeriodicLos.contains(vector->losId))
        track(mPeriodicLos, vector->losId, LosRequest{*vector}, vector->updatePeriod);
      if (answered) answer(*vector, message.arrival);
    }
  }
}

bool HostSession::addressesThisView(std::uint16_t viewId, std::uint8_t groupId) const noexcept {
  return groupId == 0 ? viewId == mView.viewId : mView.groupId != 0 && groupId == mView.groupId;
}

void HostSession::applyViewControl(const cigi::ViewControl& control) {
  if (!mView.apply || !addressesThisView(control.viewId, control.groupId)) return;  // another IG's view
  const bool finite = std::isfinite(control.xOffsetM) && std::isfinite(control.yOffsetM) &&
                      std::isfinite(control.zOffsetM) && std::isfinite(control.yawDeg) &&
                      std::isfinite(control.pitchDeg) && std::isfinite(control.rollDeg);
  if (control.entityId != 0 || !finite) {
    if (mViewControlsIgnored.fetch_add(1, std::memory_order_relaxed) == 0) {
      spdlog::warn("host: View Control for entity {} ignored: this IG's view rides the ownship (entity 0){}",
                   control.entityId, finite ? "" : ", and its values must be finite");
    }
    return;
  }
  // CIGI's offsets are in the entity's body axes, x forward, y right, z down; the view offset's
  // are x right, y forward, z up. The angles mean the same in both. Only enabled fields change.
  ViewOffset& offset = mView.offset;
  if (control.xOffsetEnabled) offset.positionM.y = control.xOffsetM;
  if (control.yOffsetEnabled) offset.positionM.x = control.yOffsetM;
  if (control.zOffsetEnabled) offset.positionM.z = -control.zOffsetM;
  if (control.yawEnabled) offset.headingRad = radians(control.yawDeg);
  if (control.pitchEnabled) offset.pitchRad = radians(control.pitchDeg);
  if (control.rollEnabled) offset.rollRad = radians(control.rollDeg);
  mView.apply(offset);
  mViewControls.fetch_add(1, std::memory_order_relaxed);
}

void HostSession::applyViewDefinition(const cigi::ViewDefinition& definition) {
  if (!mView.applyDisplay || !addressesThisView(definition.viewId, definition.groupId)) return;
  // Only the enabled half-angles change; near and far do not apply to a ray caster (it draws the
  // terrain to the horizon), pixel replication and the view type are the IG's own choices.
  FrustumAngles angles = mFrustum.value_or(mView.display.frustum());
  const auto take = [](bool enabled, float deg, double& rad) {
    if (enabled) rad = std::isfinite(deg) ? radians(deg) : std::numeric_limits<double>::quiet_NaN();
  };
  take(definition.leftEnabled, definition.leftDeg, angles.leftRad);
  take(definition.rightEnabled, definition.rightDeg, angles.rightRad);
  take(definition.topEnabled, definition.topDeg, angles.topRad);
  take(definition.bottomEnabled, definition.bottomDeg, angles.bottomRad);
  // A window each edge of which lies under 80° from the view axis (FrustumAngles::renderable), on
  // or off the axis. Orthographic views are not rendered.
  const bool renderable = angles.renderable();
  const bool supported = definition.projectionType == cigi::ProjectionType::Perspective;
  if (!renderable || !supported) {
    if (mViewDefinitionsIgnored.fetch_add(1, std::memory_order_relaxed) == 0) {
      spdlog::warn("host: View Definition ignored: {}",
                   supported
                       ? "left must lie left of right and bottom below top, each edge under 80° from the view axis"
                       : "orthographic views are not rendered");
    }
    return;
  }
  mFrustum = angles;
  mView.applyDisplay(Intrinsics::fromFrustum(mView.display.widthPx, mView.display.heightPx, angles));
  // The mirror mode has no enable: every View Definition sets it.
  if (mView.applyMirror) {
    constexpr warp::Mirror kMirrors[] = {warp::Mirror::None, warp::Mirror::Horizontal, warp::Mirror::Vertical,
                                         warp::Mirror::Both};
    mView.applyMirror(kMirrors[static_cast<unsigned>(definition.mirrorMode) & 3u]);
  }
  mViewDefinitions.fetch_add(1, std::memory_order_relaxed);
}

void HostSession::applyOwnship(const cigi::EntityControl& entity, const cigi::RateControl* rates, double hostTimeS,
                               TimePoint arrival, std::uint32_t hostFrame) {
  const std::optional<glm::dvec3> position =
      mGeoreference->toWorld({entity.latitudeDegOrXM, entity.longitudeDegOrYM, entity.altitudeMOrZM});
  if (!position) return;  // not a place on the Earth: HostMotion keeps its track
  motion::HostSample sample;
  sample.hostTimeS = hostTimeS;
  sample.arrival = arrival;
  sample.pose = Pose{*position, radians(entity.yawDeg), radians(entity.pitchDeg), radians(entity.rollDeg)};
  sample.hostFrame = hostFrame;
  sample.smooth = mSmoothing && entity.extrapolationEnabled;  // CIGI: the global enable, then the entity's
  if (rates != nullptr) {
    sample.hasRates = true;
    applyRates(*rates, sample.pose, sample.velocityMps, sample.angularRateRadS);
  }
  mOwnship.addSample(sample);
  mOwnshipUpdates.fetch_add(1, std::memory_order_relaxed);
}

template <class Request>
void HostSession::track(std::map<std::uint16_t, Periodic<Request>>& table, std::uint16_t id, const Request& request,
                        std::uint8_t updatePeriod) {
  const auto it = table.find(id);
  if (updatePeriod == 0) {
    if (it != table.end()) table.erase(it);  // the same ID, answered once: the periodic request ends
  } else if (it != table.end()) {
    it->second = {request, updatePeriod + 1};  // the request's own answer goes with the next field
  } else if (table.size() < kMaxPeriodicRequests) {
    table.emplace(id, Periodic<Request>{request, updatePeriod + 1});
  } else {
    if (mPeriodicRefused.fetch_add(1, std::memory_order_relaxed) == 0) {
      spdlog::warn("host: more than {} periodic requests of one kind; further ones are answered once",
                   kMaxPeriodicRequests);
    }
  }
  mPeriodicRequests.store(mPeriodicHeights.size() + mPeriodicLos.size(), std::memory_order_relaxed);
}

void HostSession::answerPeriodic(TimePoint now) {
  for (auto& [id, periodic] : mPeriodicHeights) {
    if (--periodic.fieldsLeft > 0) continue;
    periodic.fieldsLeft = periodic.request.updatePeriod;
    answer(periodic.request, now);
    mPeriodicAnswers.fetch_add(1, std::memory_order_relaxed);
  }
  for (auto& [id, periodic] : mPeriodicLos) {
    if (--periodic.fieldsLeft > 0) continue;
    std::visit(
        [&](const auto& request) {
          periodic.fieldsLeft = request.updatePeriod;
          answer(request, now);
        },
        periodic.request);
    mPeriodicAnswers.fetch_add(1, std::memory_order_relaxed);
  }
}

bool HostSession::refusedAsBacklog(std::size_t waiting) {
  if (waiting < kMaxAnswersQueued) return false;
  if (mRequestsRefused.fetch_add(1, std::memory_order_relaxed) == 0) {
    spdlog::warn("host: more than {} HAT/HOT or LOS requests waiting for an answer; further ones are refused",
                 kMaxAnswersQueued);
  }
  return true;
}

void HostSession::answer(const cigi::HatHotRequest& request, TimePoint arrival) {
  PendingHeight pending{request, std::nullopt, arrival + kHeightWait, {}};
  std::optional<glm::dvec3>& point = pending.pointM;
  point = placePoint(request.coordinateSystem, request.entityId, request.latitudeDegOrXM, request.longitudeDegOrYM,
                     request.altitudeMOrZM, arrival);
  if (point && insideDatabase(mTerrain->geometry(), point->x, point->y)) {
    pending.tiles = core::lineOfSightTiles(mTerrain->geometry(), *point, *point);  // the four voxels around it
  }
  if (!levelZeroResident(pending.tiles)) {
    mHeightsWaiting.push_back(std::move(pending));  // answered once the tiles are in, or at the deadline
    return;
  }
  respond(pending);
}

void HostSession::updateEntitySample(const cigi::EntityControl& entity, TimePoint arrival) {
  const bool anglesFinite =
      std::isfinite(entity.yawDeg) && std::isfinite(entity.pitchDeg) && std::isfinite(entity.rollDeg);
  const bool attached = entity.attachState == cigi::AttachState::Attached;
  // Attached: x, y, z are offsets from the parent (x forward, y right, z down); else geodetic.
  const std::optional<glm::dvec3> position =
      !anglesFinite ? std::nullopt
      : attached    ? std::optional<glm::dvec3>{{entity.latitudeDegOrXM, entity.longitudeDegOrYM, entity.altitudeMOrZM}}
                    : mGeoreference->toWorld({entity.latitudeDegOrXM, entity.longitudeDegOrYM, entity.altitudeMOrZM});
  const bool finite =
      position && std::isfinite(position->x) && std::isfinite(position->y) && std::isfinite(position->z);
  if (!finite || (attached && entity.parentId == entity.entityId)) {
    mEntitySamples.erase(entity.entityId);
    return;
  }
  HostEntitySample& sample = mEntitySamples[entity.entityId];  // its rates carry on until new ones come
  sample.id = entity.entityId;
  sample.type = entity.entityType;
  sample.at = arrival;
  sample.extrapolate = mSmoothing && entity.extrapolationEnabled;
  if (sample.attached != attached) {
    // Rates held before a change of attachment are not the entity's motion after it.
    sample.velocityMps = glm::dvec3{0.0};
    sample.angularRateRadS = glm::dvec3{0.0};
  }
  sample.attached = attached;
  if (attached) {
    sample.parentId = entity.parentId;
    // The parent's body axes (x forward, y right, z down) as a view offset's (x right, y forward, z up).
    sample.offset = ViewOffset{{position->y, position->x, -position->z},
                               radians(entity.yawDeg),
                               radians(entity.pitchDeg),
                               radians(entity.rollDeg)};
  } else {
    sample.pose = Pose{*position, radians(entity.yawDeg), radians(entity.pitchDeg), radians(entity.rollDeg)};
  }
}

void HostSession::publishEntities() {
  const std::lock_guard lock(mPublishedMutex);
  mPublishedEntities.clear();
  for (const auto& [id, sample] : mEntitySamples) mPublishedEntities.push_back(sample);
}

void HostSession::copyEntities(std::vector<HostEntitySample>& out) const {
  const std::lock_guard lock(mPublishedMutex);
  out.assign(mPublishedEntities.begin(), mPublishedEntities.end());
}

std::optional<Pose> HostSession::entityPose(std::uint16_t entityId, TimePoint at) const {
  const auto ownship = [this](TimePoint t) { return mOwnship.poseAt(t); };
  if (entityId == 0) return ownship(at);
  const auto find = [this](std::uint16_t id) -> const HostEntitySample* {
    const auto it = mEntitySamples.find(id);
    return it == mEntitySamples.end() ? nullptr : &it->second;
  };
  const HostEntitySample* sample = find(entityId);
  if (sample == nullptr) return std::nullopt;  // not tracked, or not placed
  return hostEntityPose(*sample, at, ownship, find);
}

std::optional<glm::dvec3> HostSession::placePoint(cigi::CoordinateSystem system, std::uint16_t entityId, double a,
                                                  double b, double c, TimePoint at) const {
  if (system == cigi::CoordinateSystem::Geodetic) return mGeoreference->toWorld({a, b, c});
  const std::optional<Pose> pose = entityPose(entityId, at);
  if (!pose) return std::nullopt;
  return bodyOffset(*pose, a, b, c);
}

void HostSession::answer(const cigi::LosSegmentRequest& request, TimePoint arrival) {
  PendingLos pending;
  pending.losId = request.losId;
  pending.extended = request.requestType == cigi::LosRequestType::Extended;
  pending.segment = true;
  pending.responseSystem = request.responseCoordinateSystem;
  pending.deadline = arrival + kHeightWait;
  const auto from = placePoint(request.sourceCoordinateSystem, request.entityId, request.sourceLatitudeDegOrXM,
                               request.sourceLongitudeDegOrYM, request.sourceAltitudeMOrZM, arrival);
  // CIGI 3.3: the destination may be relative to an entity of its own
  const std::uint16_t toEntity = request.destinationEntityIdValid ? request.destinationEntityId : request.entityId;
  if (request.destinationCoordinateSystem == cigi::CoordinateSystem::Entity) pending.toEntity = toEntity;
  const auto to = placePoint(request.destinationCoordinateSystem, toEntity, request.destinationLatitudeDegOrXM,
                             request.destinationLongitudeDegOrYM, request.destinationAltitudeMOrZM, arrival);
  if (request.responseCoordinateSystem == cigi::CoordinateSystem::Entity) {
    pending.responseEntity = entityPose(request.entityId, arrival);
  }
  if (request.sourceCoordinateSystem == cigi::CoordinateSystem::Entity ||
      request.destinationCoordinateSystem == cigi::CoordinateSystem::Entity) {
    pending.fromEntity = request.entityId;
  }
  if (from && to && glm::length(*to - *from) > 0.0) {
    pending.valid = true;
    pending.fromM = *from;
    pending.maxRangeM = glm::length(*to - *from);
    pending.direction = (*to - *from) / pending.maxRangeM;
  }
  queueLos(pending);
}

void HostSession::answer(const cigi::LosVectorRequest& request, TimePoint arrival) {
  PendingLos pending;
  pending.losId = request.losId;
  pending.extended = request.requestType == cigi::LosRequestType::Extended;
  pending.responseSystem = request.responseCoordinateSystem;
  pending.deadline = arrival + kHeightWait;
  const auto from = placePoint(request.sourceCoordinateSystem, request.entityId, request.sourceLatitudeDegOrXM,
                               request.sourceLongitudeDegOrYM, request.sourceAltitudeMOrZM, arrival);
  const bool entityRelative = request.sourceCoordinateSystem == cigi::CoordinateSystem::Entity;
  const std::optional<Pose> entity =
      entityRelative || request.responseCoordinateSystem == cigi::CoordinateSystem::Entity
          ? entityPose(request.entityId, arrival)
          : std::nullopt;
  if (request.responseCoordinateSystem == cigi::CoordinateSystem::Entity) pending.responseEntity = entity;
  if (entityRelative) pending.fromEntity = request.entityId;
  // Azimuth clockwise from true north (entity-relative: from the entity's x axis, in its body
  // axes), elevation up from the horizontal (from its x-y plane).
  const double az = radians(request.azimuthDeg), el = radians(request.elevationDeg);
  const double forward = std::cos(el) * std::cos(az), right = std::cos(el) * std::sin(az), up = std::sin(el);
  if (from && (!entityRelative || entity) && request.maxRangeM >= request.minRangeM && request.maxRangeM > 0.0f) {
    pending.valid = true;
    pending.fromM = *from;
    if (entityRelative) {
      const CameraAxes axes = cameraAxes(*entity);
      pending.direction = axes.forward * forward + axes.right * right + axes.up * up;
    } else {
      pending.direction = {right, forward, up};  // east, north, up
    }
    pending.minRangeM = std::clamp(static_cast<double>(request.minRangeM), 0.0, kLongestLineOfSightM);
    // A host's "unlimited" (FLT_MAX, infinity) as a range past any database: the segment's tiles
    // and the march are then made of finite numbers
    pending.maxRangeM = std::min(static_cast<double>(request.maxRangeM), kLongestLineOfSightM);
  }
  queueLos(pending);
}

void HostSession::queueLos(PendingLos pending) {
  if (pending.valid) {
    pending.tiles = core::lineOfSightTiles(mTerrain->geometry(), pending.fromM + pending.minRangeM * pending.direction,
                                           pending.fromM + pending.maxRangeM * pending.direction);
  }
  if (!levelZeroResident(pending.tiles)) {
    mLosWaiting.push_back(std::move(pending));  // answered once the tiles are in, or at the deadline
    return;
  }
  respond(pending);
}

bool HostSession::levelZeroResident(const std::vector<glm::ivec2>& tiles) {
  bool all = true;
  for (const glm::ivec2& t : tiles) {
    if (mTerrain->view().tile(0, t.x, t.y) != nullptr) continue;
    all = false;
    mTerrain->request(0, t.x, t.y, -1.0);  // ahead of the prefetch (again: a prefetch may have replaced it)
  }
  return all;
}

void HostSession::answerWaitingLos(TimePoint now) {
  std::erase_if(mLosWaiting, [&](const PendingLos& pending) {
    if (now < pending.deadline && !levelZeroResident(pending.tiles)) return false;
    respond(pending);
    return true;
  });
}

void HostSession::respond(const PendingLos& pending) {
  core::LineOfSightHit hit = pending.valid ? core::lineOfSight(mTerrain->view(), pending.fromM, pending.direction,
                                                               pending.minRangeM, pending.maxRangeM)
                                           : core::LineOfSightHit{};
  // An entity nearer than the terrain's crossing (or on a ray that met no terrain) is what it meets
  core::EntityRayHit entity;
  if (pending.valid && mEntityScene) {
    mEntityScene(mClock.now(), mEntityScratch);
    entity = core::castEntities(mEntityScratch, pending.fromM, pending.direction, pending.minRangeM,
                                hit.hit ? hit.rangeM : pending.maxRangeM, pending.fromEntity, pending.toEntity);
  }
  if (entity.hit) {
    hit.hit = true;
    hit.rangeM = entity.rangeM;
    hit.pointM = entity.pointM;
    hit.normal = entity.normal;
    hit.colourRgba = entity.rgba;
  }
  // Host entities by their CIGI id; a scripted entity has none to report
  const bool entityIdValid = entity.hit && entity.id <= 0xFFFFu;
  const auto entityId = static_cast<std::uint16_t>(entityIdValid ? entity.id : 0u);
  if (hit.hit) mLosHits.fetch_add(1, std::memory_order_relaxed);
  const auto frameLsn = static_cast<std::uint8_t>(mLastHostFrame.load(std::memory_order_relaxed) & 0x0F);
  // One answer per request (the first crossing). Valid: the ray met the terrain; Visible (Segment):
  // it did not, so the destination is seen from the source.
  if (!pending.extended) {
    cigi::LosResponse response;
    response.losId = pending.losId;
    response.valid = hit.hit;
    response.visible = pending.valid && !hit.hit && pending.segment;
    response.entityIdValid = entityIdValid;
    response.entityId = entityId;
    response.hostFrameNumberLsn = frameLsn;
    response.responseCount = 1;
    response.rangeM = hit.rangeM;
    mLosDue.push_back(response);
    return;
  }
  cigi::LosExtendedResponse response;
  response.losId = pending.losId;
  response.valid = hit.hit;
  response.rangeValid = hit.hit;
  response.visible = pending.valid && !hit.hit && pending.segment;
  response.entityIdValid = entityIdValid;
  response.entityId = entityId;
  response.hostFrameNumberLsn = frameLsn;
  response.responseCount = 1;
  if (hit.hit) {
    response.rangeM = hit.rangeM;
    if (pending.responseSystem == cigi::CoordinateSystem::Entity && pending.responseEntity) {
      // Offsets from the entity in its body axes: x forward, y right, z down.
      const CameraAxes axes = cameraAxes(*pending.responseEntity);
      const glm::dvec3 d = hit.pointM - pending.responseEntity->positionM;
      response.latitudeDegOrXM = glm::dot(d, axes.forward);
      response.longitudeDegOrYM = glm::dot(d, axes.right);
      response.altitudeMOrZM = -glm::dot(d, axes.up);
    } else if (const auto geo = mGeoreference->toGeodetic(hit.pointM)) {
      response.latitudeDegOrXM = geo->latitudeDeg;
      response.longitudeDegOrYM = geo->longitudeDeg;
      response.altitudeMOrZM = geo->altitudeM;
    }
    response.red = static_cast<std::uint8_t>(hit.colourRgba & 0xFFu);
    response.green = static_cast<std::uint8_t>((hit.colourRgba >> 8) & 0xFFu);
    response.blue = static_cast<std::uint8_t>((hit.colourRgba >> 16) & 0xFFu);
    response.alpha = static_cast<std::uint8_t>((hit.colourRgba >> 24) & 0xFFu);
    normalAngles(hit.normal, response.normalAzimuthDeg, response.normalElevationDeg);
  }
  mLosExtendedDue.push_back(response);
}

void HostSession::answerWaitingHeights(TimePoint now) {
  std::erase_if(mHeightsWaiting, [&](const PendingHeight& pending) {
    if (now < pending.deadline && !levelZeroResident(pending.tiles)) return false;
    respond(pending);
    return true;
  });
}

void HostSession::respond(const PendingHeight& pending) {
  const cigi::HatHotRequest& request = pending.request;
  const std::optional<glm::dvec3>& point = pending.pointM;
  const bool valid = point.has_value() && insideDatabase(mTerrain->geometry(), point->x, point->y);
  const double terrainM = valid ? heightOfTerrain(*mTerrain, point->x, point->y) : 0.0;
  const double aboveM = valid ? point->z - terrainM : 0.0;
  const auto frameLsn = static_cast<std::uint8_t>(mLastHostFrame.load(std::memory_order_relaxed) & 0x0F);
  if (valid) mHatHotAnswered.fetch_add(1, std::memory_order_relaxed);

  if (request.requestType == cigi::HatHotRequestType::Extended) {
    cigi::HatHotExtendedResponse response;
    response.hatHotId = request.hatHotId;
    response.valid = valid;
    response.hostFrameNumberLsn = frameLsn;
    response.heightAboveTerrainM = aboveM;
    response.heightOfTerrainM = terrainM;
    if (valid) {
      normalAngles(core::surfaceNormalAt(mTerrain->view(), point->x, point->y), response.normalAzimuthDeg,
                   response.normalElevationDeg);
    }
    mHatHotExtendedDue.push_back(response);
  } else {
    cigi::HatHotResponse response;
    response.hatHotId = request.hatHotId;
    response.valid = valid;
    response.hostFrameNumberLsn = frameLsn;
    const bool ofTerrain = request.requestType == cigi::HatHotRequestType::HeightOfTerrain;
    response.responseType =
        ofTerrain ? cigi::HatHotResponseType::HeightOfTerrain : cigi::HatHotResponseType::HeightAboveTerrain;
    response.heightM = ofTerrain ? terrainM : aboveM;
    mHatHotDue.push_back(response);
  }
}

bool HostSession::onField(const io::FieldAnnouncement& field, cigi::IgMessageBuilder& out) {
  const TimePoint now = mClock.now();
  if (mDatabases != nullptr) {
    if (std::optional<OpenDatabase> loaded = mDatabases->switchIfLoaded()) switchTo(std::move(*loaded));
  }
  // The sun moves a quarter of a degree in a minute: once a second is plenty.
  if (now - mSunPublishedAt >= std::chrono::seconds(1)) publishSun(now);
  answerPeriodic(now);
  answerWaitingHeights(now);
  answerWaitingLos(now);
  cigi::StartOfFrame sof;
  sof.databaseNumber = mDatabases != nullptr ? mDatabases->startOfFrameNumber() : mDatabaseNumber;
  sof.igMode = mMode.load(std::memory_order_relaxed);
  sof.igStatus = static_cast<std::uint8_t>(mOwnship.state(field.displayTime) == motion::HostPoseState::Holding
                                               ? HostIgStatus::OwnshipHeld
                                               : HostIgStatus::Normal);
  sof.igFrameNumber = static_cast<std::uint32_t>(field.fieldNumber);
  sof.timestampValid = true;
  sof.timestampTicks =
      static_cast<std::uint32_t>(field.displayTime.time_since_epoch().count() / 10'000);  // 10 µs ticks, wrapping
  sof.lastHostFrameNumber = mLastHostFrame.load(std::memory_order_relaxed);
  out.start(sof);
  // Answers that do not fit wait for the next field's message.
  addWhatFits(out, mHatHotDue);
  addWhatFits(out, mHatHotExtendedDue);
  addWhatFits(out, mLosDue);
  addWhatFits(out, mLosExtendedDue);
  return true;
}

void HostSession::switchTo(OpenDatabase database) {
  mTerrainOwner = std::move(database.terrain);
  mTerrain = mTerrainOwner.get();
  mGeoreference = std::move(database.georeference);
  mDatabaseNumber = database.number;
  // Requests still waiting were placed in the old database's world: answered now, as invalid.
  for (PendingHeight& pending : mHeightsWaiting) {
    pending.pointM.reset();
    pending.tiles.clear();
  }
  for (PendingLos& pending : mLosWaiting) {
    pending.valid = false;
    pending.tiles.clear();
  }
  // The ownship's kept samples are in the old world's metres: the pose follows the next sample.
  mOwnship.startNewHistory();
  // So are the other entities': placed again in the new world from their geodetic positions
  mEntitySamples.clear();
  const TimePoint now = mClock.now();
  for (const auto& [id, entity] : mEntities) updateEntitySample(entity, now);
  publishEntities();
  publishSun(now);  // another place on the Earth
}

void HostSession::publishSun(TimePoint now) {
  const std::optional<double> jd = mCelestial.julianDayAt(now);
  if (!jd) return;
  mSunPublishedAt = now;
  const core::TerrainGeometry& g = mTerrain->geometry();
  const glm::dvec3 centre{g.originM.x + 0.5 * (g.widthVox - 1) * g.spacingM,
                          g.originM.y + 0.5 * (g.heightVox - 1) * g.spacingM, 0.0};
  const std::optional<core::GeodeticPosition> place = mGeoreference->toGeodetic(centre);
  const std::optional<double> north = trueNorthInGrid(*mGeoreference, centre);
  if (!place || !north) return;  // a CRS that cannot place its own centre: the sun stays
  core::SunDirection sun = sunSeenFrom({place->latitudeDeg, place->longitudeDeg}, *jd);
  sun.azimuthDeg += *north;
  mSun.store(sun);
}

HostSessionFigures HostSession::figures() const noexcept {
  HostSessionFigures f;
  f.ownshipUpdates = mOwnshipUpdates.load(std::memory_order_relaxed);
  f.hatHotRequests = mHatHotRequests.load(std::memory_order_relaxed);
  f.hatHotAnswered = mHatHotAnswered.load(std::memory_order_relaxed);
  f.losRequests = mLosRequests.load(std::memory_order_relaxed);
  f.losHits = mLosHits.load(std::memory_order_relaxed);
  f.otherEntities = mOtherEntities.load(std::memory_order_relaxed);
  f.modeChanges = mModeChanges.load(std::memory_order_relaxed);
  f.lastHostFrame = mLastHostFrame.load(std::memory_order_relaxed);
  f.viewControls = mViewControls.load(std::memory_order_relaxed);
  f.viewControlsIgnored = mViewControlsIgnored.load(std::memory_order_relaxed);
  f.viewDefinitions = mViewDefinitions.load(std::memory_order_relaxed);
  f.viewDefinitionsIgnored = mViewDefinitionsIgnored.load(std::memory_order_relaxed);
  f.periodicRequests = mPeriodicRequests.load(std::memory_order_relaxed);
  f.periodicAnswers = mPeriodicAnswers.load(std::memory_order_relaxed);
  f.periodicRefused = mPeriodicRefused.load(std::memory_order_relaxed);
  f.requestsRefused = mRequestsRefused.load(std::memory_order_relaxed);
  f.celestialControls = mCelestialControls.load(std::memory_order_relaxed);
  f.celestialRefused = mCelestialRefused.load(std::memory_order_relaxed);
  return f;
}

}  // namespace fieldcast::app
