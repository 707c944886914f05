#pragma once
// Turning a level-0 grid (heights and colours) into a database: height quantisation, the
// pyramid (buildPyramid), tiles cut and compressed on every core, written atomically.

#include <ig_core/Progress.h>
#include <ig_core/TerrainDatabase.h>
#include <ig_core/TerrainView.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace fieldcast::core {

/// Level-0 voxels of a terrain about to become a database.
struct TerrainGrid {
  TerrainGeometry geometry;               ///< size, spacing, origin, quantisation; levels are derived
  std::vector<std::uint16_t> heightQ;     ///< W×H quantised heights, row-major (row = j, north)
  std::vector<std::uint32_t> colourRgba;  ///< W×H colours (R | G<<8 | B<<16 | A<<24)
  std::string crs;                        ///< CRS of world x, y (DatabaseLayout::crs); empty: none
  /// W×H stick ids into `sticks` (0: none), or empty when the terrain has no sticks; a voxel with a
  /// stick has its top in heightQ (Sticks.h, ObjectPlacement.h)
  std::vector<std::uint32_t> stickId;
  std::shared_ptr<const StickTable> sticks;
  /// W×H heights of the ground under the objects, kept by the placer for later placements (empty:
  /// heightQ is the ground); not stored in the database
  std::vector<std::uint16_t> groundQ;
};

/// How heights in metres map onto 16-bit steps.
struct HeightQuantisation {
  double baseM = 0.0;  ///< height of step 0
  double stepM = 0.05;
};

/// The finest "round" step (1 cm, 2 cm, 5 cm, 10 cm, …) that spans [minM, maxM] in 65535 steps,
/// with the base rounded down to a whole metre. Throws std::invalid_argument on a non-finite range.
HeightQuantisation chooseQuantisation(double minM, double maxM);

/// Quantises one height: nearest step, clamped to 0..65535. RT-safe.
std::uint16_t quantiseHeight(double heightM, const HeightQuantisation& q) noexcept;

/// Options of a database build.
struct BuildOptions {
  int tileShift = 8;  ///< tiles of 256² voxels
  VoxelColour voxelColour = VoxelColour::Rgba;
  int zstdLevel = 3;    ///< zstd's default: fast and about as small as level 9 here
  int threads = 0;      ///< 0: every core
  ProgressFn progress;  ///< stages "pyramid", "tiles"
};

/// What a build produced.
struct BuildReport {
  TerrainGeometry geometry;  ///< as written (levels filled in)
  std::uint64_t fileBytes = 0;
  std::uint64_t rawBytes = 0;  ///< uncompressed tile bytes, for the compression ratio
  std::uint64_t tileCount = 0;
};

/// Builds the pyramid of `grid`, compresses every tile and writes the database to `path`
/// atomically (nothing appears at `path` unless the whole build succeeded).
/// Throws TerrainDatabaseError (I/O) or std::invalid_argument (a grid that does not fit its geometry).
BuildReport writeTerrainDatabase(const TerrainGrid& grid, const std::filesystem::path& path,
                                 const BuildOptions& options = {});

}  // namespace fieldcast::core
