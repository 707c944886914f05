#include "SceneEntities.h"

#include <ig_core/VoxFile.h>

#include <stdexcept>

namespace fieldcast::app {

SceneEntities::SceneEntities(const std::vector<motion::ScriptedEntity>& scripted, const core::TerrainView& ground,
                             FlightClock clock)
    : mScripts(scripted), mGround(ground), mClock(std::move(clock)) {
  for (const motion::ScriptedEntity& s : mScripts) {
    try {
      mEntities.push_back({&s, std::make_shared<const core::VoxelSolid>(core::readVoxFile(s.model))});
    } catch (const std::exception& e) {
      throw std::runtime_error("entity '" + s.name + "': " + e.what());
    }
  }
}

void SceneEntities::at(TimePoint t, std::vector<core::EntityInstance>& out) const {
  out.clear();
  const double seconds = mClock(t);
  std::uint32_t id = 0;
  for (const Entity& e : mEntities) {
    core::EntityInstance instance;
    instance.id = ++id;
    instance.model = e.model;
    instance.scale = e.script->scale;
    instance.pose = e.script->path.poseAtSeconds(seconds);
    if (e.script->onGround) {
      // On the ground under it, level (a vehicle does not bank)
      instance.pose.positionM.z = mGround.heightAtM(instance.pose.positionM.x, instance.pose.positionM.y);
      instance.pose.pitchRad = instance.pose.rollRad = 0.0;
    }
    out.push_back(std::move(instance));
  }
}

}  // namespace fieldcast::app
