#include "LevelZeroGrid.h"

#include <ig_core/TerrainDatabase.h>

#include <algorithm>

namespace fieldcast::core {

LevelZeroGrid readLevelZero(const std::filesystem::path& path) {
  const DatabaseReader reader(path);
  const TerrainGeometry& g = reader.geometry();
  LevelZeroGrid grid;
  grid.geometry = g;
  const auto count = static_cast<std::size_t>(g.widthVox) * static_cast<std::size_t>(g.heightVox);
  grid.heightM.resize(count);
  grid.colourRgba.resize(count);
  const int size = g.tileSizeVox();
  TileBuffers tile;
  for (int ty = 0; ty < g.tilesY(0); ++ty) {
    for (int tx = 0; tx < g.tilesX(0); ++tx) {
      reader.readTile(0, tx, ty, tile);
      for (int y = 0; y < size && ty * size + y < g.heightVox; ++y) {
        for (int x = 0; x < size && tx * size + x < g.widthVox; ++x) {
          const std::size_t from = static_cast<std::size_t>(y) * static_cast<std::size_t>(size) + x;
          const std::size_t to = static_cast<std::size_t>(ty * size + y) * static_cast<std::size_t>(g.widthVox) +
                                 static_cast<std::size_t>(tx * size + x);
          grid.heightM[to] = static_cast<float>(g.heightM(tile.heightQ[from]));
          grid.colourRgba[to] = tile.colourRgba[from];
        }
      }
    }
  }
  return grid;
}

}  // namespace fieldcast::core
