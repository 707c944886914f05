#pragma once
// Reads of heights, colours and sticks through a window on the tile last read at each level: most
// reads of a march (the column plane march, a secondary ray's walk) are two compares and a load.
// Outside the grid or where a tile is missing they fall back to ray_march's clamped reads, which
// take a coarser level's voxel. Private to ig_core.

#include "RayMarch.h"
#include "StickShading.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace fieldcast::core {

/// One window per level on the tile last read there. The columns of a staging block share one.
struct TileWindows {
  std::array<const TerrainTile*, 24> tile{};
  std::array<int, 24> x0{};  ///< level-L voxel of the tile's corner
  std::array<int, 24> y0{};
  TileWindows() {
    x0.fill(std::numeric_limits<int>::min() / 4);
    y0.fill(std::numeric_limits<int>::min() / 4);
  }
};

/// Tile of voxel (x, y) at `level` into the window; false when it is outside the grid or missing.
inline bool windowFor(const CasterFrame& f, CasterThread& t, TileWindows& w, int level, int x, int y) noexcept {
  const auto l = static_cast<std::size_t>(level);
  const unsigned size = 1u << f.tileShift;
  if (static_cast<unsigned>(x - w.x0[l]) < size && static_cast<unsigned>(y - w.y0[l]) < size) return true;
  if (x < 0 || y < 0 || x >= f.levelWidth[l] || y >= f.levelHeight[l]) return false;
  const TerrainTile* tile = ray_march::tileAt(f, t, level, x >> f.tileShift, y >> f.tileShift);
  if (tile == nullptr) return false;
  w.tile[l] = tile;
  w.x0[l] = (x >> f.tileShift) << f.tileShift;
  w.y0[l] = (y >> f.tileShift) << f.tileShift;
  return true;
}

/// The tile of one level a march reads its heights from, meant to live in registers (a local of
/// the march): a read inside it is two unsigned compares and a load; anything else goes through the
/// window cache (TileWindows), and outside the grid or where a tile is missing through ray_march's
/// clamped reads, which take a coarser level's voxel.
struct HeightWindow {
  explicit HeightWindow(const CasterFrame& f) noexcept : shift(f.tileShift), size(1u << f.tileShift) {}
  int shift;                                     ///< the tiles' size, log2
  unsigned size;                                 ///< and in voxels
  const std::uint16_t* heights = nullptr;        ///< the tile's heights (null: none yet)
  int x0 = std::numeric_limits<int>::min() / 4;  ///< level-L voxel of the tile's corner
  int y0 = std::numeric_limits<int>::min() / 4;

  /// Forgets the tile (the march changed level).
  void reset() noexcept {
    heights = nullptr;
    x0 = y0 = std::numeric_limits<int>::min() / 4;
  }
  /// Whether voxels x .. x + dx, y .. y + dy lie in the tile (0 ≤ dx, dy < its size).
  bool holds(int x, int y, int dx = 0, int dy = 0) const noexcept {
    return static_cast<unsigned>(x - x0) < size - static_cast<unsigned>(dx) &&
           static_cast<unsigned>(y - y0) < size - static_cast<unsigned>(dy);
  }
  /// Index of voxel (x, y), which the tile holds, in its arrays.
  int index(int x, int y) const noexcept { return ((y - y0) << shift) + (x - x0); }
  /// The height of voxel (x, y) of `level` (quanta); takes its tile when the window cache has it.
  __attribute__((always_inline)) double read(const CasterFrame& f, CasterThread& t, TileWindows& w, int level, int x,
                                             int y) noexcept {
    if (holds(x, y)) return heights[index(x, y)];
    if (windowFor(f, t, w, level, x, y)) {
      const auto l = static_cast<std::size_t>(level);
      heights = w.tile[l]->heightQ;
      x0 = w.x0[l];
      y0 = w.y0[l];
      return heights[index(x, y)];
    }
    return ray_march::heightAt(f, t, level, x, y);
  }
};

/// The colour of voxel (x, y) of `level` (RGBA8) through the window.
inline std::uint32_t windowColour(const CasterFrame& f, CasterThread& t, TileWindows& w, int level, int x,
                                  int y) noexcept {
  if (!windowFor(f, t, w, level, x, y)) return ray_march::colourAt(f, t, level, x, y);
  const auto l = static_cast<std::size_t>(level);
  return w.tile[l]->colourRgba[((y - w.y0[l]) << f.tileShift) + (x - w.x0[l])];
}

/// The height of voxel (x, y) of `level` (quanta) through the window.
inline std::uint16_t windowHeight(const CasterFrame& f, CasterThread& t, TileWindows& w, int level, int x,
                                  int y) noexcept {
  if (!windowFor(f, t, w, level, x, y)) return ray_march::heightAt(f, t, level, x, y);
  const auto l = static_cast<std::size_t>(level);
  return w.tile[l]->heightQ[((y - w.y0[l]) << f.tileShift) + (x - w.x0[l])];
}

/// The stick of voxel `index` (row-major) of `tile`, a tile of `level` with stick ids: none where its
/// id is 0.
inline StickVoxel tileStick(const TerrainTile& tile, std::size_t index, int level) noexcept {
  const std::uint32_t id = tile.stickId[index];
  return id != 0 ? StickVoxel{id, tile.heightQ[index], level} : StickVoxel{};
}

/// The stick of voxel (x, y) of `level` through the window (ray_march::stickAt).
inline StickVoxel windowStick(const CasterFrame& f, CasterThread& t, TileWindows& w, int level, int x, int y) noexcept {
  if (!windowFor(f, t, w, level, x, y)) return ray_march::stickAt(f, t, level, x, y);
  const TerrainTile& tile = *w.tile[static_cast<std::size_t>(level)];
  if (tile.stickId == nullptr) return {};
  const auto index = static_cast<std::size_t>(((y - w.y0[static_cast<std::size_t>(level)]) << f.tileShift) +
                                              (x - w.x0[static_cast<std::size_t>(level)]));
  return tile.hasStick(index) ? tileStick(tile, index, level) : StickVoxel{};
}

}  // namespace fieldcast::core
