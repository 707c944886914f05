#pragma once
// Voxel models of objects (ig_core/README.md, "Objects"): a small grid of columns, each a stick of
// some height with its colours, in the model's own cells and orientation. Placing a model resamples
// it into the terrain grid (ObjectPlacement.h). The built-in library holds the trees, hedges and
// buildings the built-in terrain is furnished with.

#include <ig_core/Sticks.h>

#include <cstdint>
#include <string>
#include <vector>

namespace fieldcast::core {

/// The height of one stick voxel in every model and in the tables made from them, metres.
inline constexpr double kModelStickUnitM = 0.5;

/// A voxel model standing on the ground: widthCells × depthCells columns, row-major from its
/// south-west corner when placed at heading 0 (x east, y north); the model's centre is the centre
/// of its footprint.
struct VoxelModel {
  std::string name;
  double cellM = 2.0;  ///< a cell's side at scale 1
  int widthCells = 1;
  int depthCells = 1;
  struct Column {
    std::uint32_t stick = 0;  ///< 1-based index into `sticks`; 0: empty
    int heightUnits = 0;      ///< stick voxels from the ground to the top
  };
  std::vector<Column> columns;     ///< widthCells × depthCells
  std::vector<StickEntry> sticks;  ///< the model's kinds of stick, colours from the top down
};

/// The models of the built-in library, by name: "conifer", "broadleaf", "hedge", "house",
/// "barn", "church". Deterministic.
const std::vector<VoxelModel>& builtinModels();

/// The built-in model called `name`, or nullptr.
const VoxelModel* findBuiltinModel(const std::string& name);

}  // namespace fieldcast::core
