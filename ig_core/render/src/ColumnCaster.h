#pragma once
// The fast ray caster's entry points, and the frame and worker state its two marches share (the
// column-plane march, PlaneMarch.h, and the per-ray march, RayMarch.h).
// Private to ig_core; Renderer drives it through the RenderPool.

#include "Shading.h"
#include "StickShading.h"

#include <ig_core/RenderSettings.h>
#include <ig_core/TerrainView.h>
#include <ig_core/ViewGeometry.h>

#include <fieldcast/Image.h>

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace fieldcast::core {

/// Highest quantised height anywhere in the terrain (max over the top level's max mip).
std::uint16_t terrainCeilingQ(const TerrainView& view) noexcept;
/// Colour of the base plane beyond the terrain's edge: the mean colour of the top level (always
/// resident), RGBA8.
std::uint32_t basePlaneColour(const TerrainView& view) noexcept;

/// Everything one frame's columns need, read-only while the columns are cast.
struct CasterFrame {
  /// Casts the frame's `footprint` (null: every pixel).
  CasterFrame(const TerrainView& view, const ViewGeometry& geometry, const RenderSettings& settings,
              std::uint16_t ceilingQ, std::uint32_t baseColourRgba, Image* image, float* rangeM,
              const FrameFootprint* footprint = nullptr) noexcept;

  /// What a ray that missed the terrain sees (world z `dz`, `length` per metre of depth): the base
  /// plane, or the sky; `rangeOutM` gets the range (infinite for the sky). RT-safe.
  Rgb missed(double dz, double length, float& rangeOutM) const noexcept {
    rangeOutM = static_cast<float>(basePlaneRangeM(baseAboveM, dz, length));
    return shading.missed(baseColour, rangeOutM, static_cast<float>(dz / length));
  }

  const TerrainView* view;
  const ViewGeometry* geo;
  Shading shading;
  int levels;
  int tileShift;
  int tileMask;
  int supersample;
  bool blend;
  std::array<int, 24> levelWidth{};   ///< voxels of each level along x
  std::array<int, 24> levelHeight{};  ///< voxels of each level along y
  double camX, camY;                  ///< camera in level-0 voxel-centre units
  double camZq;                       ///< camera height in height quanta
  double unitsPerM;                   ///< level-0 units per metre (1 / spacing)
  double quantaPerM;                  ///< height quanta per metre
  double ceilingQ;                    ///< highest terrain height, quanta
  double invLodDepth0M;               ///< 1 / ViewGeometry::lodDepth0M()
  double baseAboveM;                  ///< camera height over the base plane (quantised height 0)
  std::uint32_t baseColourRgba;       ///< the base plane's colour, RGBA8
  Rgb baseColour;                     ///< the same, unpacked and lit by the frame's sun
  /// The columns of a staging block march in step, in depth bands this ratio deep (see
  /// castColumns; below 1 acts as 1). Any value gives the same image; tests set it near 1 to pause
  /// at almost every crossing, and to infinity to march each column to its end.
  double marchBand = 1.5;
  /// Neighbouring columns' plane marches in step (RenderSettings::laneMarch, LaneMarch.h).
  bool laneMarch = false;
  const StickTable* sticks;     ///< the terrain's sticks, or null when it has none
  bool seeThrough = false;      ///< some of them are complex: a ray may go on as a secondary ray
  double stickUnitsPerQ = 0.0;  ///< stick voxels (level 0) per height quantum
  double stickReachQ = 0.0;     ///< the tallest stick's length, height quanta (0: no sticks)
  /// The march looks past a crossing for terrain rising above the column plane's line where a
  /// voxel spans at least this many pixels (lookPastVoxelPx in PlaneMarch.h)
  double lookPastVoxelPx = 8.0;
  FrameFootprint footprint;  ///< the frame's pixels to cast; each column repeats its end pixels beyond
  Image* image;              ///< output pixels (or null)
  float* rangeM;             ///< output range per pixel (or null)
};

/// Per-worker state: a tile pointer per level (most lookups are one compare) and counters.
struct alignas(64) CasterThread {
  struct CachedTile {
    int tx = -1;
    int ty = -1;
    const TerrainTile* tile = nullptr;
  };
  std::array<CachedTile, 24> tiles{};
  std::uint64_t steps = 0;          ///< height samples taken (march steps)
  std::uint64_t rays = 0;           ///< rays cast
  std::uint64_t runs = 0;           ///< fast-loop runs started (profiling)
  std::uint64_t generic = 0;        ///< generic (slow-path) samples (profiling)
  std::uint64_t retraces = 0;       ///< rays whose start lay below the surface (profiling)
  std::uint64_t firstHits = 0;      ///< max-pyramid descents (profiling)
  std::uint64_t pauses = 0;         ///< column plane marches paused at a depth band's end (profiling)
  std::uint64_t secondaryRays = 0;  ///< rays gone on through a complex stick's see-through texel
  /// Columns are cast into these column-major blocks, then copied into the frame (see castColumns).
  /// They grow to the tallest frame once; after that the worker allocates nothing.
  static constexpr int kStagingColumns = 16;
  std::vector<std::uint8_t> columnPixels;
  std::vector<float> columnRanges;
  void resetTiles() noexcept { tiles.fill(CachedTile{}); }
};

/// What one ray saw: the terrain, the base plane beyond its edge (also a hit), or the sky.
struct CastResult {
  bool hit = false;
  int level = 0;             ///< level of detail the hit was found at
  double depthM = 0.0;       ///< depth (forward-axis distance) of the hit
  glm::dvec3 pointM{0.0};    ///< world hit point
  std::uint32_t colour = 0;  ///< terrain colour at the hit (level blend not applied), or the base plane's
};

/// Casts columns [u0, u1) of the frame into its image (and range). Allocation-free once the
/// worker's staging blocks have grown to the frame's height.
void castColumns(const CasterFrame& frame, int u0, int u1, CasterThread& thread) noexcept;

/// The same columns cast ray by ray (each ray marched on its own line, starting where the ray
/// below hit). Slower; kept as the straightforward form of the coherent march and tested against
/// castColumns. RT-safe, allocation-free.
void castColumnsPerRay(const CasterFrame& frame, int u0, int u1, CasterThread& thread) noexcept;

/// Casts one ray through continuous frame pixel (u, v) from the camera, with the same march as
/// the columns (first hit by the max pyramid, then grid-line stepping). RT-safe.
CastResult castRay(const CasterFrame& frame, double u, double v, CasterThread& thread) noexcept;

}  // namespace fieldcast::core
