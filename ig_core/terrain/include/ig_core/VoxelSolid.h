#pragma once
// A solid of cubic voxels: what fieldcast-sculpt carves and what a MagicaVoxel .vox file holds
// (VoxFile.h). Placed in a terrain it becomes a VoxelModel of sticks (toVoxelModel).

#include <ig_core/ObjectModels.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fieldcast::core {

/// A voxel's side at scale 1, metres: the stick unit, so a solid's layers are its sticks' voxels.
inline constexpr double kSolidVoxelM = kModelStickUnitM;

/// sizeX × sizeY × sizeZ voxels: x the model's right (east at heading 0), y its front (north), z up;
/// x fastest, then y, then z. A voxel is RGBA8 (R in the low byte); alpha 0 is empty.
struct VoxelSolid {
  int sizeX = 0, sizeY = 0, sizeZ = 0;
  std::vector<std::uint32_t> rgba;

  std::size_t index(int x, int y, int z) const noexcept {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(sizeY) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(sizeX) +
           static_cast<std::size_t>(x);
  }
  bool filled(int x, int y, int z) const noexcept { return (rgba[index(x, y, z)] >> 24) != 0; }
  std::size_t filledCount() const noexcept;
};

/// An empty solid of the given size (each 1 … 4096; std::invalid_argument otherwise).
VoxelSolid emptySolid(int sizeX, int sizeY, int sizeZ);

/// The solid as a model of sticks, cells kSolidVoxelM wide: a column stands from the ground to its
/// topmost voxel, its colours top down (opaque, whatever alpha the file gave them); one with gaps
/// below its top is a complex stick whose gaps are cavities (kCavityRgba). Columns of the same
/// colours share one stick (uniform where all are one colour). Throws std::invalid_argument for a
/// solid with no voxel.
VoxelModel toVoxelModel(const VoxelSolid& solid, std::string name);

}  // namespace fieldcast::core
