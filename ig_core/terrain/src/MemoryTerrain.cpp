// A fully resident terrain: the pyramid built and cut into tiles, every tile published.
#include <ig_core/MemoryTerrain.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace fieldcast::core {

MemoryTerrain::MemoryTerrain(TerrainGeometry geometry, std::span<const std::uint16_t> heightQ,
                             std::span<const std::uint32_t> colourRgba, std::span<const std::uint32_t> stickId,
                             std::shared_ptr<const StickTable> sticks) {
  if (geometry.levels <= 0) geometry.levels = geometry.maxLevels();
  if (!stickId.empty()) {
    const std::uint32_t entries = sticks ? sticks->size() : 0;
    const auto bad = std::find_if(stickId.begin(), stickId.end(), [&](std::uint32_t id) { return id > entries; });
    if (bad != stickId.end()) {
      throw std::invalid_argument("MemoryTerrain: stick id " + std::to_string(*bad) + " with " +
                                  std::to_string(entries) + " table entries");
    }
  }
  mView = std::make_unique<TerrainView>(geometry, std::move(sticks));
  const Pyramid pyramid = buildPyramid(geometry, heightQ, colourRgba, stickId);
  const auto tileVoxels = static_cast<std::size_t>(geometry.tileSizeVox()) * geometry.tileSizeVox();
  for (int level = 0; level < geometry.levels; ++level) {
    for (int ty = 0; ty < geometry.tilesY(level); ++ty) {
      for (int tx = 0; tx < geometry.tilesX(level); ++tx) {
        auto owned = std::make_unique<OwnedTile>();
        owned->heightQ.resize(tileVoxels);
        owned->maxHeightQ.resize(tileVoxels);
        owned->colourRgba.resize(tileVoxels);
        owned->stickId.resize(stickId.empty() ? 0 : tileVoxels);
        cutTile(pyramid[static_cast<std::size_t>(level)], geometry.tileShift, tx, ty, owned->heightQ, owned->maxHeightQ,
                owned->colourRgba, owned->stickId);
        if (std::all_of(owned->stickId.begin(), owned->stickId.end(), [](std::uint32_t id) { return id == 0; })) {
          owned->stickId.clear();  // a tile without sticks says so with a null array
        }
        owned->stickBits = stickBitsOf(owned->stickId);
        owned->tile = TerrainTile{owned->heightQ.data(), owned->maxHeightQ.data(), owned->colourRgba.data(),
                                  owned->stickId.empty() ? nullptr : owned->stickId.data(),
                                  owned->stickId.empty() ? nullptr : owned->stickBits.data()};
        mView->publish(level, tx, ty, &owned->tile);
        mTiles.push_back(std::move(owned));
      }
    }
  }
}

}  // namespace fieldcast::core
