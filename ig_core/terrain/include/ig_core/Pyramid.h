#pragma once
// The binary pyramid of DESIGN.md §2, built on every core: each level halves the one below with a
// 2×2 box filter (heights and colours), and a conservative max mip bounds the surface for
// empty-space skipping. Level 0 is not copied: it reads the arrays the pyramid was built from.

#include <ig_core/TerrainView.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace fieldcast::core {

/// One pyramid level as row-major arrays (row = j, north).
struct PyramidLevel {
  int widthVox = 0;
  int heightVox = 0;
  std::span<const std::uint16_t> heightQ;     ///< 2×2 box-filtered heights (rounded)
  std::span<const std::uint16_t> maxHeightQ;  ///< see TerrainView::maxHeightQ
  std::span<const std::uint32_t> colourRgba;  ///< 2×2 box-filtered colours
  std::span<const std::uint32_t> stickId;     ///< stick ids (the tallest stick below), empty: no sticks
};

/// Every level of a terrain. Level 0's heights, colours and stick ids are the arrays given to
/// buildPyramid, which must outlive it; the coarser levels and every max mip are its own.
class Pyramid {
 public:
  Pyramid() = default;
  Pyramid(Pyramid&&) noexcept = default;
  Pyramid& operator=(Pyramid&&) noexcept = default;
  Pyramid(const Pyramid&) = delete;
  Pyramid& operator=(const Pyramid&) = delete;

  std::size_t size() const noexcept { return mLevels.size(); }
  const PyramidLevel& operator[](std::size_t level) const noexcept { return mLevels[level]; }

 private:
  friend Pyramid buildPyramid(const TerrainGeometry&, std::span<const std::uint16_t>, std::span<const std::uint32_t>,
                              std::span<const std::uint32_t>, int);
  // A level's own arrays, allocated without zero-filling: the threads that fill a level's rows
  // touch their pages first
  struct Storage {
    std::unique_ptr<std::uint16_t[]> heightQ;
    std::unique_ptr<std::uint16_t[]> maxHeightQ;
    std::unique_ptr<std::uint32_t[]> colourRgba;
    std::unique_ptr<std::uint32_t[]> stickId;
  };
  std::vector<PyramidLevel> mLevels;  // spans into mStorage (or, level 0, the caller's arrays)
  std::vector<Storage> mStorage;
};

/// Builds all `geometry.levels` levels from level-0 heights, colours and stick ids (W×H each;
/// no stick ids: no sticks), on `threads` threads (0: every core); the same pyramid for any
/// thread count. A coarse voxel over a stick takes the tallest one's top and id.
/// Throws std::invalid_argument when the sizes do not match the geometry.
Pyramid buildPyramid(const TerrainGeometry& geometry, std::span<const std::uint16_t> heightQ,
                     std::span<const std::uint32_t> colourRgba, std::span<const std::uint32_t> stickId = {},
                     int threads = 0);

/// Copies tile (tx, ty) of a level into `heightQ`, `maxHeightQ`, `colourRgba` and, when not
/// empty, `stickId` (tileSize² each), repeating the edge voxels beyond the level's border.
void cutTile(const PyramidLevel& level, int tileShift, int tx, int ty, std::span<std::uint16_t> heightQ,
             std::span<std::uint16_t> maxHeightQ, std::span<std::uint32_t> colourRgba,
             std::span<std::uint32_t> stickId = {});

}  // namespace fieldcast::core
