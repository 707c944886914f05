#pragma once
// The moving entities of the scene (ig_core/Entities.h): what a flight file scripts, posed on
// the flight's clock for the instant each frame is rendered for.

#include <ig_core/Entities.h>
#include <ig_core/TerrainView.h>
#include <motion/FlightFile.h>

#include <fieldcast/Time.h>

#include <functional>
#include <memory>
#include <vector>

namespace fieldcast::app {

class SceneEntities {
 public:
  /// Seconds on the flight's clock at an instant (the flight's time 0 moves when it is reset).
  using FlightClock = std::function<double(TimePoint)>;

  /// Reads each entity's model (a .vox file; throws std::runtime_error naming the entity and the
  /// file). `ground` gives the height of entities on the ground and must outlive this.
  SceneEntities(const std::vector<motion::ScriptedEntity>& scripted, const core::TerrainView& ground,
                FlightClock clock);

  std::size_t size() const noexcept { return mEntities.size(); }

  /// Every entity at instant `t`, in `out` (cleared first; its capacity is kept). Render thread.
  void at(TimePoint t, std::vector<core::EntityInstance>& out) const;

 private:
  struct Entity {
    const motion::ScriptedEntity* script;
    std::shared_ptr<const core::VoxelSolid> model;
  };
  std::vector<motion::ScriptedEntity> mScripts;
  std::vector<Entity> mEntities;
  const core::TerrainView& mGround;
  FlightClock mClock;
};

}  // namespace fieldcast::app
