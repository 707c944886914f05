#pragma once
// The moving entities of the scene (ig_core/Entities.h): what a flight file scripts, posed on
// the flight's clock for the instant each frame is rendered for.

#include <service/ServiceConfig.h>

#include <ig_core/Entities.h>
#include <ig_core/TerrainView.h>
#include <motion/FlightFile.h>

#include <fieldcast/Conventions.h>
#include <fieldcast/Time.h>

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <vector>

namespace fieldcast::app {

/// A host's entity (CIGI Entity Control, an id other than the ownship's) as last sent.
struct HostEntitySample {
  std::uint16_t id = 0;
  std::uint16_t type = 0;
  Pose pose;                        ///< world, at `at` (a detached entity)
  glm::dvec3 velocityMps{0.0};      ///< world (its Rate Control; zero without one)
  glm::dvec3 angularRateRadS{0.0};  ///< heading, pitch, roll rates
  TimePoint at{};                   ///< when the pose holds (its message's arrival)
  bool extrapolate = true;          ///< the entity's and IG Control's extrapolation enables
  /// Attached to entity `parentId` (0: the ownship): placed at `offset` from the parent's pose
  /// (position in the parent's axes: x right, y forward, z up; angles after the parent's), and
  /// moving with it; `pose` and the rates are not used.
  bool attached = false;
  std::uint16_t parentId = 0;
  ViewOffset offset;
};

/// How far a host entity is extrapolated past its last sample at most (then it holds).
inline constexpr Nanoseconds kMaxEntityExtrapolation = std::chrono::milliseconds(500);

/// The host entity's pose at `t`: its sample moved on by its rates (at most
/// kMaxEntityExtrapolation, and not at all when it may not be extrapolated). RT-safe.
Pose extrapolateEntity(const HostEntitySample& sample, TimePoint t) noexcept;

/// The ownship's pose at an instant (the parent of entities attached to entity 0).
using OwnshipPose = std::function<Pose(TimePoint)>;
/// A host entity's sample by id; null when there is none.
using FindHostEntity = std::function<const HostEntitySample*(std::uint16_t)>;
/// Attachments resolved at most this deep (a longer chain is a loop the host made).
inline constexpr int kMaxAttachDepth = 8;

/// The world pose at `t` of `sample`: extrapolateEntity when detached; attached, its offset from
/// its parent's pose at `t` (the ownship's for parent 0, else the parent `find` gives, resolved
/// the same way). Nothing when a parent is missing (or the ownship's pose is not given) or the
/// chain is deeper than kMaxAttachDepth.
std::optional<Pose> hostEntityPose(const HostEntitySample& sample, TimePoint t, const OwnshipPose& ownship,
                                   const FindHostEntity& find);

class SceneEntities {
 public:
  /// Seconds on the flight's clock at an instant (the flight's time 0 moves when it is reset).
  using FlightClock = std::function<double(TimePoint)>;

  /// Reads each entity's model (a .vox file; throws std::runtime_error naming the entity and the
  /// file). `ground` gives the height of entities on the ground and must outlive this (null: no
  /// entity may be on the ground).
  SceneEntities(const std::vector<motion::ScriptedEntity>& scripted, const core::TerrainView* ground,
                FlightClock clock);

  SceneEntities(const SceneEntities&) = delete;  // it points into its own scripts
  SceneEntities& operator=(const SceneEntities&) = delete;

  std::size_t size() const noexcept { return mEntities.size(); }

  /// The host's entities as last sent, into the vector given (Any thread; HostSession::copyEntities).
  using HostEntities = std::function<void(std::vector<HostEntitySample>&)>;
  /// A model per CIGI entity type (a .vox file, read here; throws std::runtime_error naming the
  /// type and the file) for the host's entities; an entity of another type is not drawn.
  /// `ownship` places the entities attached to the ownship (null: they are not drawn).
  void setHost(HostEntities entities, const std::vector<HostEntityModel>& models, OwnshipPose ownship = {});

  /// Every entity at instant `t`, in `out` (cleared first; its capacity is kept): a host entity
  /// with its CIGI id, a scripted one with an id from 0x10000 on. Any thread.
  void at(TimePoint t, std::vector<core::EntityInstance>& out) const;

 private:
  struct Entity {
    const motion::ScriptedEntity* script;
    std::shared_ptr<const core::VoxelSolid> model;
  };
  struct HostModel {
    std::shared_ptr<const core::VoxelSolid> model;
    double scale = 1.0;
  };
  HostEntities mHost;
  OwnshipPose mOwnship;
  std::map<std::uint16_t, HostModel> mHostModels;
  std::vector<motion::ScriptedEntity> mScripts;
  std::vector<Entity> mEntities;
  const core::TerrainView* mGround;
  FlightClock mClock;
};

}  // namespace fieldcast::app
