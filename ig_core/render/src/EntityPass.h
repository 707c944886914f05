#pragma once
// The entity pass (Entities.h): after the terrain's columns, each entity's voxel grid is ray-cast
// inside its screen bounding box, one ray through each pixel's centre, and composited by range.

#include "Shading.h"

#include <ig_core/Entities.h>
#include <ig_core/ViewGeometry.h>

#include <fieldcast/Frame.h>

#include <span>

namespace fieldcast::core {

/// Where a ray meets an entity.
struct EntityHit {
  double depthM = 0.0;               ///< along the camera's forward axis (the ray's parameter, ViewGeometry::ray)
  glm::dvec3 normal{0.0, 0.0, 1.0};  ///< world normal of the face the ray entered through
  std::uint32_t rgba = 0;
};

/// The first voxel of `entity` the ray `origin + t·ray` (t > 0, ViewGeometry::ray scaling) meets,
/// if any nearer than `maxDepthM`. Amanatides & Woo's grid traversal in the model's axes. RT-safe.
bool castEntity(const EntityInstance& entity, const glm::dvec3& origin, const glm::dvec3& ray, double maxDepthM,
                EntityHit& hit) noexcept;

/// Frame pixels [u0, u1) × [v0, v1).
struct PixelBox {
  int u0 = 0, v0 = 0, u1 = 0, v1 = 0;
  bool empty() const noexcept { return u0 >= u1 || v0 >= v1; }
};

/// The pixels of `geometry`'s frame that `entity`'s box may cover: its corners projected, the box
/// clipped to the near plane first (a box reaching behind the eye covers the side of the screen
/// it is on, not the whole of it); empty when it lies wholly behind. Every pixel whose ray meets
/// the entity lies inside. RT-safe.
PixelBox entityScreenBox(const EntityInstance& entity, const ViewGeometry& geometry) noexcept;

/// Draws `entities` into `frame` (image, range image, control points) where they are nearer than
/// the range image holds. `frame.rangeM` must be filled. Returns the pixels drawn. RT-safe.
std::size_t drawEntities(std::span<const EntityInstance> entities, const ViewGeometry& geometry, const Shading& shading,
                         Frame& frame) noexcept;

}  // namespace fieldcast::core
