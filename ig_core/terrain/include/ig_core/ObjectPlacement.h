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

/// One object to place: a model (which must outlive the placing) and where, as ObjectPlacement.
struct PlacementRequest {
  const VoxelModel* model = nullptr;
  double xM = 0.0, yM = 0.0;
  double headingDeg = 0.0;
  double scale = 1.0;
};

/// Places objects into a grid (for generators that make millions): heights, stick ids and top
/// colours as each is placed, the stick table (the grid's entries kept, the models' added) at
/// finish(). Objects are placed in the order given, whether one by one or in batches.
class ObjectPlacer {
 public:
  /// Requests of a batch whose footprints are held at once (a forest is millions of trees).
  static constexpr std::size_t kBatchRequests = 16384;

  /// Throws std::invalid_argument when the grid's arrays do not match its size, or its stick table
  /// has another unit than the models.
  explicit ObjectPlacer(TerrainGrid& grid);
  ObjectPlacer(const ObjectPlacer&) = delete;
  ObjectPlacer& operator=(const ObjectPlacer&) = delete;

  /// Places `model` with its footprint's centre at world (xM, yM); false when none of it landed on
  /// the grid. Throws std::invalid_argument for a scale out of range or a non-finite position.
  bool place(const VoxelModel& model, double xM, double yM, double headingDeg, double scale);
  /// Places every request in order, as place() one by one would, the footprints found on
  /// `threads` threads (0: every core). A request place() would refuse (or one without a model)
  /// throws the same error, after the requests before it are placed; finish() then installs the
  /// table of what was placed. (An allocation failing while a footprint is written leaves that
  /// object half placed.)
  void place(std::span<const PlacementRequest> requests, int threads);
  /// The ground under level-0 voxel k: the heights before any object was placed. Until finish().
  std::uint16_t groundQ(std::size_t k) const noexcept { return mGround[k]; }
  /// Installs the stick table into the grid and says what was done. Once, after the last place().
  PlacementReport finish();

 private:
  // A voxel whose centre falls in a placement's footprint, and the stick the model puts there
  struct FootprintVoxel {
    std::size_t k = 0;               // the level-0 voxel
    std::uint32_t stick = 0;         // the model's stick (1-based)
    std::uint16_t topQ = 0;          // its top, over the lowest ground of the footprint
    int heightUnits = 0;             // the model column's height
    std::uint32_t placedLength = 0;  // a complex stick's length down to this voxel's ground, else 0
  };
  struct Footprint {
    const VoxelModel* model = nullptr;
    std::vector<FootprintVoxel> voxels;  // those not buried by the slope
  };
  // Reads only the ground and the model: safe on several threads at once
  void findFootprint(const PlacementRequest& request, Footprint& out) const;
  // Writes the voxels where no taller stick stands; the stick table grows as new sticks are used
  bool apply(const Footprint& footprint);
  std::uint32_t tableId(const VoxelModel& model, std::uint32_t stick, std::uint32_t placedLength);

  TerrainGrid& mGrid;
  std::vector<std::uint16_t> mGround;  // the ground under the objects (TerrainGrid::groundQ)
  std::vector<StickEntry> mEntries;
  // (model, its stick, the length placed: 0 but for a complex stick) → table id
  std::map<std::tuple<const VoxelModel*, std::uint32_t, std::uint32_t>, std::uint32_t> mIdOf;
  Footprint mFootprint;  // reused by place() one by one
  PlacementReport mReport;
};

/// Places `objects` into `grid` in order (ObjectPlacer), on `threads` threads (0: every core).
/// Throws std::invalid_argument for an unknown model (naming the known ones), a scale out of
/// range, or a non-finite position.
PlacementReport placeObjects(TerrainGrid& grid, std::span<const ObjectPlacement> objects,
                             const ModelLookup& lookup = findBuiltinModel, int threads = 0);

}  // namespace fieldcast::core
