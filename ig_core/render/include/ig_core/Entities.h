#pragma once
// Moving entities (ig_core/README.md, "Entities"): voxel models drawn at a pose in every frame,
// after the terrain, each ray-cast through its own small grid and kept where it is nearer than
// what the frame's range image already holds (so a hill hides a vehicle, and the nearer of two
// entities wins). The range image and the control points see them.

#include <ig_core/VoxelSolid.h>

#include <fieldcast/Pose.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>

namespace fieldcast::core {

/// One entity to draw in a frame, at the frame's pose time.
struct EntityInstance {
  std::uint32_t id = 0;
  std::shared_ptr<const VoxelSolid> model;  ///< voxels of kSolidVoxelM × scale; null: nothing drawn
  /// The model's footprint centre at its base (world metres) and its attitude: heading clockwise
  /// from north turns its front (+y) there, pitch raises its front, roll lowers its right (Pose's
  /// conventions, DESIGN.md §6).
  Pose pose;
  double scale = 1.0;
};

/// Where a line of sight meets the nearest of a set of entities.
struct EntityRayHit {
  bool hit = false;
  std::uint32_t id = 0;  ///< the entity's EntityInstance::id
  double rangeM = 0.0;   ///< along the ray
  glm::dvec3 pointM{0.0};
  glm::dvec3 normal{0.0, 0.0, 1.0};  ///< world normal of the voxel face it meets
  std::uint32_t rgba = 0;            ///< the voxel's colour
};

/// The first voxel of any of `entities` but `excludeId` (the entity a line of sight starts from)
/// and `alsoExcludeId` (the one a segment ends at) on the ray from `originM` along the unit
/// `direction`, with a range in [minRangeM, maxRangeM] (an entity nearer than minRangeM is not
/// seen, even where it reaches past it). The same grid walk as the entity pass. RT-safe.
EntityRayHit castEntities(std::span<const EntityInstance> entities, const glm::dvec3& originM,
                          const glm::dvec3& direction, double minRangeM, double maxRangeM,
                          std::optional<std::uint32_t> excludeId = std::nullopt,
                          std::optional<std::uint32_t> alsoExcludeId = std::nullopt) noexcept;

}  // namespace fieldcast::core
