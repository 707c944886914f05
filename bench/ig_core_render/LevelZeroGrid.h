#pragma once
// A terrain's level 0 as two plain arrays (heights in metres, colours), read from its database:
// what the independent renderers of fieldcast_bench_table draw.

#include <ig_core/TerrainView.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace fieldcast::core {

struct LevelZeroGrid {
  TerrainGeometry geometry;
  std::vector<float> heightM;             ///< widthVox × heightVox, row j = north
  std::vector<std::uint32_t> colourRgba;  ///< the same voxels' colours

  float height(int i, int j) const noexcept {
    return heightM[static_cast<std::size_t>(j) * static_cast<std::size_t>(geometry.widthVox) + i];
  }
  std::uint32_t colour(int i, int j) const noexcept {
    return colourRgba[static_cast<std::size_t>(j) * static_cast<std::size_t>(geometry.widthVox) + i];
  }
};

/// Reads every level-0 tile of the database at `path`. Throws TerrainDatabaseError as the reader does.
LevelZeroGrid readLevelZero(const std::filesystem::path& path);

}  // namespace fieldcast::core
