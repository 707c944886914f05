#pragma once
// The built-in terrain: a deterministic, seeded landscape a pilot would take for real — a coast
// with a bay, an estuary and an island in the south; farmland plains; a river meandering south
// out of a glacial valley; the Long Ridge standing out of the foothills; fold mountains with
// east-west ridges in the north. Generated once into a cache folder and reused.
//
// World frame: the south-west voxel centre is at (0, 0); x east, y north, metres. Feature
// positions scale with the terrain's extent; builtinLandmarks() gives them in world metres (the
// figures for the default 8192² at 2 m are listed in ig_core/README.md).

#include <ig_core/Progress.h>
#include <ig_core/TerrainBuilder.h>
#include <ig_core/TerrainColour.h>

#include <glm/vec2.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace fieldcast::core {

/// Which built-in terrain: size, spacing, seed and whether it is furnished fully determine it.
struct BuiltinTerrainSpec {
  int sizeVox = 8192;      ///< voxels per side (≥ 64)
  double spacingM = 2.0;   ///< voxel pitch
  std::uint64_t seed = 1;  ///< varies the noise and the river's meanders, not the layout
  /// Furnished with objects (ObjectPlacement.h): woods on its forests, hedgerows along its fields,
  /// villages with a church along its river. Without: the bare land (for comparisons).
  bool objects = true;
};

/// Bumped whenever the generator's output changes, so stale caches are not reused.
inline constexpr int kBuiltinGeneratorVersion = 6;

/// A named place of the built-in terrain, for scripting flights.
struct BuiltinLandmark {
  std::string name;      ///< e.g. "river_mouth"
  glm::dvec2 positionM;  ///< world x east, y north
  double groundM = 0.0;  ///< approximate ground (or water surface) height there, before fine detail
  std::string description;
};

/// The landmarks of `spec`: coast, bay, island, river mouth and valley, the Long Ridge, plains, mountains.
std::vector<BuiltinLandmark> builtinLandmarks(const BuiltinTerrainSpec& spec);

/// Heights of the built-in terrain and where the water is.
struct BuiltinHeights {
  TerrainGeometry geometry;               ///< origin (0, 0), quantisation base −10 m, step 5 cm
  std::vector<std::uint16_t> heightQ;     ///< W×H, row-major (row = j, north); water voxels hold the water surface
  std::vector<std::uint8_t> waterDepthM;  ///< 0 on land, else water depth in metres (1..255)
};

/// Generates the heights of `spec` on `threads` threads (0: every core). Deterministic: the same
/// spec gives the same voxels for any thread count. Reports stage "terrain". Throws
/// std::invalid_argument for a size below 64 or above kMaxDatabaseSideVox.
BuiltinHeights generateBuiltinHeights(const BuiltinTerrainSpec& spec, int threads = 0, const ProgressFn& progress = {});

/// Heights plus procedural colour (stage "colour") and, when the spec asks, its objects (stage
/// "objects"), ready for writeTerrainDatabase. Deterministic.
TerrainGrid generateBuiltinTerrain(const BuiltinTerrainSpec& spec, const ProceduralColourOptions& colour = {},
                                   const ProgressFn& progress = {});

/// The cache folder: $FIELDCAST_CACHE_DIR, else $XDG_CACHE_HOME/fieldcast, else ~/.cache/fieldcast.
std::filesystem::path defaultCacheDir();

/// File name of `spec`'s database inside a cache folder (encodes generator version, size, spacing, seed).
std::filesystem::path builtinDatabasePath(const std::filesystem::path& cacheDir, const BuiltinTerrainSpec& spec);

/// Returns the path of `spec`'s database in `cacheDir`, generating it first when it is missing or
/// unreadable (creating the folder; serialised across processes by a lock file). `progress`
/// empty: a ConsoleProgress (bar on a terminal, log lines otherwise). Throws TerrainDatabaseError.
std::filesystem::path ensureBuiltinDatabase(const std::filesystem::path& cacheDir, const BuiltinTerrainSpec& spec,
                                            const ProgressFn& progress = {}, int threads = 0);

}  // namespace fieldcast::core
