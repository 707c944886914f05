#pragma once
// A terrain held wholly in memory: level-0 heights and colours in, the binary pyramid (filtered
// heights and colours, conservative max mip) built and cut into tiles, every tile published.
// Used for small terrains, synthetic test terrains, and as the builder of database tiles.

#include <ig_core/TerrainView.h>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace fieldcast::core {

/// One full pyramid level as plain row-major arrays (row = j, north).
struct PyramidLevel {
  int widthVox = 0;
  int heightVox = 0;
  std::vector<std::uint16_t> heightQ;     ///< 2×2 box-filtered heights (rounded)
  std::vector<std::uint16_t> maxHeightQ;  ///< see TerrainView::maxHeightQ
  std::vector<std::uint32_t> colourRgba;  ///< 2×2 box-filtered colours
  std::vector<std::uint32_t> stickId;     ///< stick ids (the tallest stick below), empty: no sticks
};

/// Builds all `geometry.levels` levels from level-0 heights, colours and stick ids (W×H each;
/// no stick ids: no sticks). A coarse voxel over a stick takes the tallest one's top and id.
/// Throws std::invalid_argument when the sizes do not match the geometry.
std::vector<PyramidLevel> buildPyramid(const TerrainGeometry& geometry, std::span<const std::uint16_t> heightQ,
                                       std::span<const std::uint32_t> colourRgba,
                                       std::span<const std::uint32_t> stickId = {});

/// Copies tile (tx, ty) of a level into `heightQ`, `maxHeightQ`, `colourRgba` and, when not
/// empty, `stickId` (tileSize² each), repeating the edge voxels beyond the level's border.
void cutTile(const PyramidLevel& level, int tileShift, int tx, int ty, std::span<std::uint16_t> heightQ,
             std::span<std::uint16_t> maxHeightQ, std::span<std::uint32_t> colourRgba,
             std::span<std::uint32_t> stickId = {});

/// A fully resident terrain. Not copyable; the view stays valid as long as the object lives.
class MemoryTerrain {
 public:
  /// `geometry.levels` ≤ 0 picks geometry.maxLevels(). `stickId` (W×H, or empty: no sticks)
  /// points into `sticks`. Throws std::invalid_argument on sizes that do not match or an id
  /// beyond the table.
  MemoryTerrain(TerrainGeometry geometry, std::span<const std::uint16_t> heightQ,
                std::span<const std::uint32_t> colourRgba, std::span<const std::uint32_t> stickId = {},
                std::shared_ptr<const StickTable> sticks = {});
  MemoryTerrain(const MemoryTerrain&) = delete;
  MemoryTerrain& operator=(const MemoryTerrain&) = delete;

  const TerrainView& view() const noexcept { return *mView; }
  const TerrainGeometry& geometry() const noexcept { return mView->geometry(); }

 private:
  struct OwnedTile {
    std::vector<std::uint16_t> heightQ;
    std::vector<std::uint16_t> maxHeightQ;
    std::vector<std::uint32_t> colourRgba;
    std::vector<std::uint32_t> stickId;  // empty when the tile has none
    TerrainTile tile;
  };
  std::unique_ptr<TerrainView> mView;
  std::vector<std::unique_ptr<OwnedTile>> mTiles;
};

}  // namespace fieldcast::core
