#pragma once
// Placing objects (ig_core/README.md, "Objects"): voxel models resampled into a terrain grid as
// sticks. Each placement names a model, where its footprint's centre stands (world metres), its
// heading (clockwise from north: the model's north points there) and its scale. The model stands
// on the lowest ground under its footprint (so it never floats; on a slope its uphill side is
// shorter); a voxel takes the model cell its centre falls in (nearest). Where objects overlap the
// taller stick wins. Every kind of stick a model has becomes one entry of the terrain's shared
// stick table however often the model is placed.

#include <ig_core/ObjectModels.h>
#include <ig_core/TerrainBuilder.h>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace fieldcast::core {

struct ObjectPlacement {
  std::string model;
  double xM = 0.0, yM = 0.0;  ///< world position of the footprint's centre
  double headingDeg = 0.0;    ///< clockwise from north
  double scale = 1.0;         ///< horizontal and vertical
};

/// Scales a placement may have.
inline constexpr double kMinObjectScale = 0.25;
inline constexpr double kMaxObjectScale = 4.0;

/// Reads a placement list: CSV with the header `model,x,y,heading,scale` (heading and scale may be
/// left out of the header, and then of every row: 0° and 1), `#` comments and blank lines
/// ignored. Throws std::runtime_error naming the file and line of anything else.
std::vector<ObjectPlacement> readPlacementList(const std::filesystem::path& path);

/// What placing did.
struct PlacementReport {
  std::size_t placed = 0;       ///< objects with at least one voxel on the grid
  std::size_t offGrid = 0;      ///< objects wholly off the grid (or below the ground everywhere)
  std::size_t stickVoxels = 0;  ///< level-0 voxels carrying a stick afterwards
  std::uint32_t tableEntries = 0;
};

/// Finds a model by name (nullptr: unknown).
using ModelLookup = std::function<const VoxelModel*(const std::string&)>;

/// Places objects into a grid one by one (for generators that make millions): heights, stick ids
/// and top colours as each is placed, the stick table (the grid's entries kept, the models'
/// added) at finish().
class ObjectPlacer {
 public:
  /// Throws std::invalid_argument when the grid's arrays do not match its size, or its stick table
  /// has another unit than the models.
  explicit ObjectPlacer(TerrainGrid& grid);
  ObjectPlacer(const ObjectPlacer&) = delete;
  ObjectPlacer& operator=(const ObjectPlacer&) = delete;

  /// Places `model` with its footprint's centre at world (xM, yM); false when none of it landed on
  /// the grid. Throws std::invalid_argument for a scale out of range or a non-finite position.
  bool place(const VoxelModel& model, double xM, double yM, double headingDeg, double scale);
  /// Installs the stick table into the grid and says what was done. Once, after the last place().
  PlacementReport finish();

 private:
  TerrainGrid& mGrid;
  std::vector<std::uint16_t> mGround;  // the ground under the objects (TerrainGrid::groundQ)
  std::vector<StickEntry> mEntries;
  // (model, its stick, the length placed: 0 but for a complex stick) → table id
  std::map<std::tuple<const VoxelModel*, std::uint32_t, std::uint32_t>, std::uint32_t> mIdOf;
  std::vector<std::pair<std::size_t, const VoxelModel::Column*>> mFootprint;  // reused
  PlacementReport mReport;
};

/// Places `objects` into `grid` (ObjectPlacer). Throws std::invalid_argument for an unknown model
/// (naming the known ones), a scale out of range, or a non-finite position.
PlacementReport placeObjects(TerrainGrid& grid, std::span<const ObjectPlacement> objects,
                             const ModelLookup& lookup = findBuiltinModel);

}  // namespace fieldcast::core
