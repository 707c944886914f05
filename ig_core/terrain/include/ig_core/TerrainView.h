#pragma once
// The renderer's window onto the terrain (DESIGN.md §2): a binary pyramid of voxel levels, each
// level cut into square tiles, read without locks from any number of render threads.
//
// Layout (why): heights and colours are kept as separate arrays (structure of arrays). The ray
// march reads a height at every step and a colour only where it hits, so 16-bit heights packed
// 32 to a cache line keep the march's working set small; the colour (RGBA8) is fetched once per
// pixel. The seed packed height and colour into one 4-byte voxel; that doubles the bytes the march
// drags through the cache for no gain here.
//
// Grid: level L has ceil(W / 2^L) × ceil(H / 2^L) voxels. Voxel (i, j) of level L covers level-0
// voxels [i·2^L, (i+1)·2^L) × [j·2^L, (j+1)·2^L); its centre lies at
// originM + ((i + ½)·2^L − ½)·spacingM on each axis (level-0 voxel centres at originM + i·spacingM).
// Row j runs east along i; j grows to the north.

#include <ig_core/Sticks.h>

#include <glm/vec2.hpp>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace fieldcast::core {

/// Where the level-0 grid lies in the world, how heights are quantised, and how it is tiled.
struct TerrainGeometry {
  int widthVox = 0;              ///< level-0 voxels along x (east)
  int heightVox = 0;             ///< level-0 voxels along y (north)
  double spacingM = 2.0;         ///< level-0 voxel pitch in metres (dx = dy)
  glm::dvec2 originM{0.0, 0.0};  ///< world x, y of the centre of level-0 voxel (0, 0)
  double heightBaseM = 0.0;      ///< world z of quantised height 0
  double heightStepM = 0.05;     ///< metres per quantisation step: z = base + q·step
  int levels = 1;                ///< pyramid levels; level 0 is the finest
  int tileShift = 8;             ///< tiles are (1 << tileShift)² voxels at every level

  int tileSizeVox() const noexcept { return 1 << tileShift; }
  int levelWidthVox(int level) const noexcept { return (widthVox + (1 << level) - 1) >> level; }
  int levelHeightVox(int level) const noexcept { return (heightVox + (1 << level) - 1) >> level; }
  int tilesX(int level) const noexcept { return (levelWidthVox(level) + tileSizeVox() - 1) >> tileShift; }
  int tilesY(int level) const noexcept { return (levelHeightVox(level) + tileSizeVox() - 1) >> tileShift; }
  double heightM(std::uint16_t q) const noexcept { return heightBaseM + heightStepM * q; }
  /// Levels that a grid of this size can have: down to one tile or less at the top.
  int maxLevels() const noexcept;
};

/// One tile of one level: (1 << tileShift)² voxels, row-major (row = j, north), immutable once
/// published. Voxels beyond the level's edge repeat the edge voxel.
struct TerrainTile {
  const std::uint16_t* heightQ = nullptr;     ///< filtered quantised heights of this level
  const std::uint16_t* maxHeightQ = nullptr;  ///< conservative max mip, see TerrainView::maxHeightQ
  const std::uint32_t* colourRgba = nullptr;  ///< RGBA8, bytes R, G, B, A in memory order
  /// Stick ids (0: none; else an entry of TerrainView::sticks()), or nullptr when the tile has no
  /// stick: the height of a voxel with a stick is its stick's top (Sticks.h).
  const std::uint32_t* stickId = nullptr;
  /// Bit k (word k / 64, bit k % 64) set where stickId[k] is not 0, or nullptr with stickId: which
  /// voxels have a stick, in 1/32 of the id plane's bytes (a caster asks it of most crossings;
  /// most of a furnished tile's voxels have none).
  const std::uint64_t* stickBits = nullptr;

  /// Whether voxel `index` (row-major in the tile) has a stick. Call only where stickId is set.
  bool hasStick(std::size_t index) const noexcept { return (stickBits[index >> 6] >> (index & 63)) & 1u; }
};

/// TerrainTile::stickBits of a tile's stick ids (empty for none).
std::vector<std::uint64_t> stickBitsOf(std::span<const std::uint32_t> stickId);

/// Lock-free tile table over all levels. The owner of the tiles (MemoryTerrain, the tile cache)
/// publishes and withdraws tiles; renderers read them. The top level is always resident, so every
/// query has an answer: a voxel whose tile is missing is answered by the finest resident coarser
/// level, and the miss is counted. Never blocks, never does I/O.
class TerrainView {
 public:
  /// A view of `geometry` whose tiles' stick ids point into `sticks` (none: a terrain without sticks).
  explicit TerrainView(const TerrainGeometry& geometry, std::shared_ptr<const StickTable> sticks = {});
  TerrainView(const TerrainView&) = delete;
  TerrainView& operator=(const TerrainView&) = delete;

  const TerrainGeometry& geometry() const noexcept { return mGeometry; }
  int levels() const noexcept { return mGeometry.levels; }
  /// The shared stick table, or nullptr when the terrain has no sticks. RT-safe.
  const StickTable* sticks() const noexcept { return mSticks.get(); }

  /// Tile (tx, ty) of `level`, or nullptr when it is not resident. RT-safe, lock-free.
  /// The load is seq_cst (a plain load on x86-64 and arm64, like acquire): TileCache's lease
  /// rule needs it ordered with the lease slots in one total order (TileCache.cpp, lease()).
  const TerrainTile* tile(int level, int tx, int ty) const noexcept {
    const Level& l = mLevels[static_cast<std::size_t>(level)];
    return l.slots[static_cast<std::size_t>(ty * l.tilesX + tx)].load(std::memory_order_seq_cst);
  }

  /// Quantised height of voxel (i, j) of `level`, clamped to the grid. RT-safe.
  std::uint16_t heightQ(int level, int i, int j) const noexcept { return sample(level, i, j).heightQ; }
  /// Colour of voxel (i, j) of `level` (RGBA8 packed R | G<<8 | B<<16 | A<<24), clamped. RT-safe.
  std::uint32_t colourRgba(int level, int i, int j) const noexcept { return sample(level, i, j).colour; }
  /// Conservative maximum: ≥ every height of levels 0..`level` whose voxel centre lies within one
  /// level-`level` voxel of voxel (i, j), so it bounds the bilinear surface of those levels over
  /// the voxel's area. Clamped to the grid. RT-safe.
  std::uint16_t maxHeightQ(int level, int i, int j) const noexcept { return sample(level, i, j).maxQ; }

  /// One voxel: height, max mip and colour, with the level that actually answered.
  struct Sample {
    std::uint16_t heightQ = 0;
    std::uint16_t maxQ = 0;
    std::uint32_t colour = 0;
    std::uint32_t stickId = 0;  ///< 0: no stick
    int level = 0;              ///< ≥ the level asked for when its tile was missing
  };
  /// The voxel (i, j) of `level` (clamped), falling back to coarser resident levels. RT-safe.
  Sample sample(int level, int i, int j) const noexcept;

  /// Terrain height in metres at world (x, y), bilinear between the voxel centres of `level`.
  /// Outside the grid the edge voxels extend. RT-safe.
  double heightAtM(double xM, double yM, int level = 0) const noexcept;

  /// Queries answered by a coarser level because a tile was missing, since construction.
  std::uint64_t missCount() const noexcept { return mMisses.load(std::memory_order_relaxed); }

  /// Makes `tile` visible at (level, tx, ty); nullptr withdraws it. For tile owners only; the
  /// owner keeps the tile's memory alive until no renderer can still hold the old pointer.
  void publish(int level, int tx, int ty, const TerrainTile* tile) noexcept;

 private:
  struct Level {
    int tilesX = 0;
    int tilesY = 0;
    std::unique_ptr<std::atomic<const TerrainTile*>[]> slots;
  };
  TerrainGeometry mGeometry;
  std::shared_ptr<const StickTable> mSticks;
  std::vector<Level> mLevels;
  mutable std::atomic<std::uint64_t> mMisses{0};
};

}  // namespace fieldcast::core
