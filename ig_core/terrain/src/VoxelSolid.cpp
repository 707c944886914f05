#include <ig_core/VoxelSolid.h>

#include <algorithm>
#include <map>
#include <stdexcept>
#include <utility>

namespace fieldcast::core {

std::size_t VoxelSolid::filledCount() const noexcept {
  return static_cast<std::size_t>(
      std::count_if(rgba.begin(), rgba.end(), [](std::uint32_t c) { return (c >> 24) != 0; }));
}

VoxelSolid emptySolid(int sizeX, int sizeY, int sizeZ) {
  const auto valid = [](int n) { return n >= 1 && n <= 4096; };
  if (!valid(sizeX) || !valid(sizeY) || !valid(sizeZ)) {
    throw std::invalid_argument("a voxel solid of " + std::to_string(sizeX) + " × " + std::to_string(sizeY) + " × " +
                                std::to_string(sizeZ) + " voxels (each side 1 … 4096)");
  }
  VoxelSolid solid{sizeX, sizeY, sizeZ, {}};
  solid.rgba.assign(static_cast<std::size_t>(sizeX) * static_cast<std::size_t>(sizeY) * static_cast<std::size_t>(sizeZ),
                    0u);
  return solid;
}

VoxelModel toVoxelModel(const VoxelSolid& solid, std::string name) {
  VoxelModel model{std::move(name), kSolidVoxelM, solid.sizeX, solid.sizeY, {}, {}};
  model.columns.assign(static_cast<std::size_t>(solid.sizeX) * static_cast<std::size_t>(solid.sizeY), {});
  std::map<std::vector<std::uint32_t>, std::uint32_t> stickOf;  // colours top down → 1-based stick
  for (int y = 0; y < solid.sizeY; ++y)
    for (int x = 0; x < solid.sizeX; ++x) {
      int top = solid.sizeZ - 1;
      while (top >= 0 && !solid.filled(x, y, top)) --top;
      if (top < 0) continue;
      std::vector<std::uint32_t> texels;
      for (int z = top; z >= 0; --z)
        texels.push_back(solid.filled(x, y, z) ? (solid.rgba[solid.index(x, y, z)] | kOpaqueRgba) : kCavityRgba);
      auto [it, added] = stickOf.try_emplace(texels, 0u);
      if (added) {
        const bool uniform = std::all_of(texels.begin(), texels.end(), [&](std::uint32_t c) { return c == texels[0]; });
        const bool cavity = std::find(texels.begin(), texels.end(), kCavityRgba) != texels.end();
        const StickKind kind = cavity ? StickKind::Complex : uniform ? StickKind::Uniform : StickKind::Textured;
        StickEntry entry{kind, static_cast<std::uint32_t>(texels.size()),
                         kind == StickKind::Uniform ? std::vector<std::uint32_t>{texels[0]} : texels};
        model.sticks.push_back(std::move(entry));
        it->second = static_cast<std::uint32_t>(model.sticks.size());
      }
      model.columns[static_cast<std::size_t>(y) * static_cast<std::size_t>(solid.sizeX) + static_cast<std::size_t>(x)] =
          {it->second, top + 1};
    }
  if (model.sticks.empty()) throw std::invalid_argument("model '" + model.name + "': the solid has no voxel");
  return model;
}

}  // namespace fieldcast::core
