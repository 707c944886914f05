#pragma once
// A terrain held wholly in memory: level-0 heights and colours in, the binary pyramid (Pyramid.h)
// built and cut into tiles, every tile published. Used for small terrains and synthetic test
// terrains.

#include <ig_core/Pyramid.h>
#include <ig_core/TerrainView.h>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace fieldcast::core {

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
    std::vector<std::uint64_t> stickBits;
    TerrainTile tile;
  };
  std::unique_ptr<TerrainView> mView;
  std::vector<std::unique_ptr<OwnedTile>> mTiles;
};

}  // namespace fieldcast::core
