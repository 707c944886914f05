#pragma once
// The [terrain] section of the service configuration (keys in config/README.md): which database
// the IG renders, and how much memory its tile cache may hold.

#include <ig_core/BuiltinTerrain.h>
#include <ig_core/TileCache.h>

#include <fieldcast/ConfigReader.h>

#include <cstddef>
#include <filesystem>
#include <memory>

namespace fieldcast::core {

/// What [terrain] sets.
struct TerrainConfig {
  std::filesystem::path database;  ///< a database file; empty: the built-in terrain
  std::filesystem::path cacheDir;  ///< where the built-in terrain is generated once; empty: the default
  BuiltinTerrainSpec builtin;      ///< size and seed of the built-in terrain
  std::size_t memoryBudgetBytes = std::size_t{1024} << 20;  ///< tile cache budget
};

/// Reads [terrain] (source, cache_dir, builtin_size, builtin_seed, memory_budget_mb). Throws ConfigError.
TerrainConfig readTerrainConfig(ConfigReader& table);

/// Opens the configured terrain (the built-in one generated on first use). Throws
/// std::runtime_error prefixed "terrain.source: ".
std::unique_ptr<TileCache> openTerrain(const TerrainConfig& config);

}  // namespace fieldcast::core
