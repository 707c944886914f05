#pragma once
// Line of sight against the terrain the renderer draws at full resolution: a world ray marched
// over the bilinear level-0 surface (TerrainView::heightAtM) in steps of 1/8 voxel, the crossing
// refined by bisection — the reference renderer's method (ReferenceRenderer.cpp), at level 0
// only. Where the ray stays above a coarser voxel's max mip (levels 8 down to 1) it jumps across
// that voxel instead: no crossing can lie there. For the CIGI host's LOS requests (app
// HostSession) and any tool that needs a range.
//
// Tiles: the march reads whatever is resident; where a level-0 tile is missing the view answers
// from a coarser level (TerrainView::sample). Callers wanting the full-resolution answer make the
// level-0 tiles along the ray resident first (lineOfSightTiles lists them).

#include <ig_core/TerrainView.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace fieldcast::core {

/// Where a ray meets the terrain.
struct LineOfSightHit {
  bool hit = false;                  ///< false: the ray leaves the database (or reaches maxRangeM) above the surface
  double rangeM = 0.0;               ///< distance from the ray's origin to the crossing
  glm::dvec3 pointM{0.0};            ///< world point of the crossing
  glm::dvec3 normal{0.0, 0.0, 1.0};  ///< unit normal of the drawn surface there (slope across one voxel)
  std::uint32_t colourRgba = 0;      ///< bilinear level-0 colour there, unshaded (RGBA8 as TerrainView packs it)
};

/// Marches from `originM` along `direction` (any non-zero length) between `minRangeM` and
/// `maxRangeM` metres from the origin. An origin already below the surface at minRangeM hits there.
/// Only the hull of the level-0 voxel centres is searched (outside it there is no terrain to meet).
LineOfSightHit lineOfSight(const TerrainView& view, const glm::dvec3& originM, const glm::dvec3& direction,
                           double minRangeM, double maxRangeM) noexcept;

/// Unit normal of the bilinear level-0 surface at world (x, y): central differences over ±half a
/// voxel (the slope across one voxel), the same normal HAT/HOT Extended answers give.
glm::dvec3 surfaceNormalAt(const TerrainView& view, double xM, double yM) noexcept;

/// Level-0 tiles (tx, ty) the segment from `fromM` to `toM` passes over (each tile once), clipped
/// to the grid: what to make resident before asking lineOfSight for a full-resolution answer.
std::vector<glm::ivec2> lineOfSightTiles(const TerrainGeometry& g, const glm::dvec3& fromM, const glm::dvec3& toM);

}  // namespace fieldcast::core
