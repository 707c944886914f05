#include <ig_core/TerrainConfig.h>

#include <ig_core/OpenTerrain.h>

#include <cstdint>
#include <stdexcept>
#include <string>

namespace fieldcast::core {

TerrainConfig readTerrainConfig(ConfigReader& t) {
  TerrainConfig c;
  if (t.string("source", "builtin") != "builtin") c.database = t.path("source", "");
  // Empty: $FIELDCAST_CACHE_DIR, else $XDG_CACHE_HOME/fieldcast, else ~/.cache/fieldcast.
  if (!t.string("cache_dir", "").empty()) c.cacheDir = t.path("cache_dir", "");
  c.builtin.sizeVox = static_cast<int>(t.integer("builtin_size", c.builtin.sizeVox, 256, 65536));
  if ((c.builtin.sizeVox & (c.builtin.sizeVox - 1)) != 0) t.fail("builtin_size", "expected a power of two");
  c.builtin.seed =
      static_cast<std::uint64_t>(t.integer("builtin_seed", static_cast<std::int64_t>(c.builtin.seed), 0, INT64_MAX));
  c.memoryBudgetBytes = static_cast<std::size_t>(t.integer(
                            "memory_budget_mb", static_cast<std::int64_t>(c.memoryBudgetBytes >> 20), 16, 1 << 20))
                        << 20;
  t.finish();
  return c;
}

std::unique_ptr<TileCache> openTerrain(const TerrainConfig& config) {
  const std::string source = config.database.empty() ? "builtin" : config.database.string();
  try {
    return openTerrain(source, config.cacheDir, config.memoryBudgetBytes, config.builtin);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("terrain.source: ") + e.what());
  }
}

}  // namespace fieldcast::core
