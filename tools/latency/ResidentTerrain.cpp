#include "ResidentTerrain.h"

#include <ig_core/OpenTerrain.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>

namespace fieldcast::tools {

std::unique_ptr<core::TileCache> openResidentDatabase(const std::filesystem::path& path, std::size_t budgetBytes) {
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error("--db " + path.string() + ": no such file");
  auto cache = core::openTerrain(path.string(), {}, budgetBytes);
  const core::TerrainGeometry& g = cache->geometry();
  std::uint64_t tiles = 0;
  for (int level = g.levels - 1; level >= 0; --level) {  // coarse first: they are pinned already
    for (int ty = 0; ty < g.tilesY(level); ++ty) {
      for (int tx = 0; tx < g.tilesX(level); ++tx) {
        cache->request(level, tx, ty);
        ++tiles;
      }
    }
  }
  if (!cache->waitIdle(std::chrono::minutes(30))) {
    throw std::runtime_error("--db " + path.string() + ": the tiles did not load within 30 minutes");
  }
  const core::TileCacheStats s = cache->stats();
  if (s.loadFailures > 0) {
    throw std::runtime_error("--db " + path.string() + ": " + std::to_string(s.loadFailures) +
                             " tiles could not be read (fieldcast-db verify names them)");
  }
  if (s.residentTiles < tiles || s.evictions > 0) {
    const double perTile =
        s.residentTiles > 0 ? static_cast<double>(s.residentBytes) / static_cast<double>(s.residentTiles) : 0.0;
    char needed[64];
    std::snprintf(needed, sizeof needed, "%.0f", perTile * static_cast<double>(tiles) / (1 << 20) * 1.1 + 1.0);
    throw std::runtime_error("--db " + path.string() + ": its " + std::to_string(tiles) +
                             " tiles do not fit in --db-budget-mb " + std::to_string(budgetBytes >> 20) + " (about " +
                             needed + " MB needed)");
  }
  return cache;
}

std::optional<std::string> whereFlightLeavesTerrain(const EvaluatedFlight& flight, const core::TerrainGeometry& terrain,
                                                    const EvaluationSpec& spec) {
  // The grid's extent: voxel centres from the origin, half a voxel beyond each edge
  const double half = 0.5 * terrain.spacingM;
  const double west = terrain.originM.x - half, south = terrain.originM.y - half;
  const double east = west + terrain.widthVox * terrain.spacingM;
  const double north = south + terrain.heightVox * terrain.spacingM;
  const double end = spec.startS + toSeconds(spec.fieldRate.tickOffset(spec.fields));
  for (double t = std::max(0.0, spec.startS - 1.0); t <= end; t += 0.01) {
    const glm::dvec3 p = flight.poseAtSeconds(t).positionM;
    if (p.x < west || p.x > east || p.y < south || p.y > north) {
      char where[256];
      std::snprintf(where, sizeof where,
                    "flight '%s' is at (%.1f, %.1f) at %.2f s, outside the terrain's x %.1f … %.1f, y %.1f … %.1f",
                    flight.name().c_str(), p.x, p.y, t, west, east, south, north);
      return std::string(where);
    }
  }
  return std::nullopt;
}

}  // namespace fieldcast::tools
