#include "SceneEntities.h"

#include <ig_core/VoxFile.h>

#include <algorithm>
#include <stdexcept>

namespace fieldcast::app {

Pose extrapolateEntity(const HostEntitySample& sample, TimePoint t) noexcept {
  Pose pose = sample.pose;
  if (!sample.extrapolate) return pose;
  const double dt = toSeconds(std::clamp(t - sample.at, Nanoseconds{0}, kMaxEntityExtrapolation));
  pose.positionM += sample.velocityMps * dt;
  pose.headingRad += sample.angularRateRadS.x * dt;
  pose.pitchRad += sample.angularRateRadS.y * dt;
  pose.rollRad += sample.angularRateRadS.z * dt;
  return pose;
}

std::optional<Pose> hostEntityPose(const HostEntitySample& sample, TimePoint t, const OwnshipPose& ownship,
                                   const FindHostEntity& find) {
  // Up the chain of parents to a detached entity or the ownship, then back down its offsets.
  std::vector<const ViewOffset*> offsets;
  const HostEntitySample* at = &sample;
  Pose base;
  for (;;) {
    if (!at->attached) {
      base = extrapolateEntity(*at, t);
      break;
    }
    if (offsets.size() >= static_cast<std::size_t>(kMaxAttachDepth)) return std::nullopt;
    offsets.push_back(&at->offset);
    if (at->parentId == 0) {
      if (!ownship) return std::nullopt;
      base = ownship(t);
      break;
    }
    at = find(at->parentId);
    if (at == nullptr) return std::nullopt;
  }
  for (auto it = offsets.rbegin(); it != offsets.rend(); ++it) base = offsetPose(base, **it);
  return base;
}

SceneEntities::SceneEntities(const std::vector<motion::ScriptedEntity>& scripted, const core::TerrainView* ground,
                             FlightClock clock)
    : mScripts(scripted), mGround(ground), mClock(std::move(clock)) {
  for (const motion::ScriptedEntity& s : mScripts) {
    if (s.onGround && mGround == nullptr)
      throw std::runtime_error("entity '" + s.name + "': on the ground of no terrain");
    try {
      mEntities.push_back({&s, std::make_shared<const core::VoxelSolid>(core::readVoxFile(s.model))});
    } catch (const std::exception& e) {
      throw std::runtime_error("entity '" + s.name + "': " + e.what());
    }
  }
}

void SceneEntities::setHost(HostEntities entities, const std::vector<HostEntityModel>& models, OwnshipPose ownship) {
  mOwnship = std::move(ownship);
  for (const HostEntityModel& m : models) {
    try {
      mHostModels[m.type] = {std::make_shared<const core::VoxelSolid>(core::readVoxFile(m.model)), m.scale};
    } catch (const std::exception& e) {
      throw std::runtime_error("host.entity_model type " + std::to_string(m.type) + ": " + e.what());
    }
  }
  mHost = std::move(entities);
}

void SceneEntities::at(TimePoint t, std::vector<core::EntityInstance>& out) const {
  out.clear();
  const double seconds = mClock(t);
  std::uint32_t id = 0x10000u;  // apart from the host's ids
  for (const Entity& e : mEntities) {
    core::EntityInstance instance;
    instance.id = id++;
    instance.model = e.model;
    instance.scale = e.script->scale;
    instance.pose = e.script->path.poseAtSeconds(seconds);
    if (e.script->onGround) {
      // On the ground under it, level (a vehicle does not bank)
      instance.pose.positionM.z = mGround->heightAtM(instance.pose.positionM.x, instance.pose.positionM.y);
      instance.pose.pitchRad = instance.pose.rollRad = 0.0;
    }
    out.push_back(std::move(instance));
  }
  if (!mHost) return;
  std::vector<HostEntitySample> host;
  mHost(host);
  const FindHostEntity find = [&host](std::uint16_t wanted) -> const HostEntitySample* {
    const auto it =
        std::find_if(host.begin(), host.end(), [wanted](const HostEntitySample& s) { return s.id == wanted; });
    return it == host.end() ? nullptr : &*it;
  };
  for (const HostEntitySample& sample : host) {
    const auto model = mHostModels.find(sample.type);
    if (model == mHostModels.end()) continue;
    const std::optional<Pose> pose = hostEntityPose(sample, t, mOwnship, find);
    if (!pose) continue;  // attached to an entity that is not there
    core::EntityInstance instance;
    instance.id = sample.id;
    instance.model = model->second.model;
    instance.scale = model->second.scale;
    instance.pose = *pose;
    out.push_back(std::move(instance));
  }
}

}  // namespace fieldcast::app
