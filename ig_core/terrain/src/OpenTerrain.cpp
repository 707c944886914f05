#include <ig_core/OpenTerrain.h>

#include <cstdlib>

namespace fieldcast::core {

std::unique_ptr<TileCache> openTerrain(const std::string& source, const std::filesystem::path& cacheDir,
                                       std::size_t budgetBytes, const BuiltinTerrainSpec& builtin,
                                       const TileCacheOptions& cacheOptions) {
  TileCacheOptions options = cacheOptions;
  options.budgetBytes = budgetBytes;
  std::filesystem::path path;
  if (source == "builtin") {
    std::filesystem::path dir = cacheDir.empty() ? defaultCacheDir() : cacheDir;
    const std::string text = dir.string();
    if (text.rfind("~/", 0) == 0) {
      const char* home = std::getenv("HOME");
      if (home != nullptr) dir = std::filesystem::path(home) / text.substr(2);
    }
    path = ensureBuiltinDatabase(dir, builtin);
  } else {
    path = source;
  }
  return std::make_unique<TileCache>(std::make_unique<DatabaseTileSource>(path), options);
}

}  // namespace fieldcast::core
