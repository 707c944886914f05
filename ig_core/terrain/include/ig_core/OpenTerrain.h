#pragma once
// The one entry point the service calls to get its terrain.

#include <ig_core/BuiltinTerrain.h>
#include <ig_core/TileCache.h>

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>

namespace fieldcast::core {

/// Opens the terrain the service renders. `source` is "builtin" (the built-in terrain `builtin`,
/// generated once into `cacheDir` and reused; a progress bar on a terminal while it builds) or the
/// path of a database made by `fieldcast-db build`. `cacheDir` empty: defaultCacheDir(); a leading
/// "~/" is expanded. The result gives view(), prefetch(), heightAtM() and stats().
/// Throws TerrainDatabaseError naming the file and what was wrong.
std::unique_ptr<TileCache> openTerrain(const std::string& source, const std::filesystem::path& cacheDir,
                                       std::size_t budgetBytes, const BuiltinTerrainSpec& builtin = {},
                                       const TileCacheOptions& cacheOptions = {});

}  // namespace fieldcast::core
