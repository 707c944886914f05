// Level-0 grid → pyramid → compressed tiles → database file (written atomically).
#include <ig_core/Pyramid.h>
#include <ig_core/TerrainBuilder.h>

#include "Parallel.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <mutex>
#include <stdexcept>

namespace fieldcast::core {

HeightQuantisation chooseQuantisation(double minM, double maxM) {
  if (!std::isfinite(minM) || !std::isfinite(maxM) || maxM < minM) {
    throw std::invalid_argument("chooseQuantisation: invalid height range");
  }
  HeightQuantisation q;
  q.baseM = std::floor(minM);
  const double span = maxM - q.baseM;
  static constexpr std::array<double, 15> kSteps = {0.01, 0.02, 0.05, 0.1,  0.2,  0.25,  0.5,   1.0,
                                                    2.0,  5.0,  10.0, 20.0, 50.0, 100.0, 1000.0};
  q.stepM = kSteps.back();
  for (const double step : kSteps) {
    if (span / step <= 65535.0) {
      q.stepM = step;
      break;
    }
  }
  return q;
}

std::uint16_t quantiseHeight(double heightM, const HeightQuantisation& q) noexcept {
  const double steps = std::round((heightM - q.baseM) / q.stepM);
  return static_cast<std::uint16_t>(std::clamp(steps, 0.0, 65535.0));
}

BuildReport writeTerrainDatabase(const TerrainGrid& grid, const std::filesystem::path& path,
                                 const BuildOptions& options) {
  DatabaseLayout layout;
  layout.geometry = grid.geometry;
  layout.geometry.tileShift = options.tileShift;
  layout.geometry.levels = 1;
  layout.geometry.levels = layout.geometry.maxLevels();
  layout.voxelColour = options.voxelColour;
  layout.crs = grid.crs;
  const TerrainGeometry& g = layout.geometry;
  if (g.widthVox < 1 || g.heightVox < 1 || g.widthVox > kMaxDatabaseSideVox || g.heightVox > kMaxDatabaseSideVox ||
      options.tileShift < kMinTileShift || options.tileShift > kMaxTileShift) {
    throw std::invalid_argument("writeTerrainDatabase: grid " + std::to_string(g.widthVox) + "x" +
                                std::to_string(g.heightVox) + " or tile shift " + std::to_string(options.tileShift) +
                                " out of range");
  }
  const std::uint32_t stickEntries = grid.sticks ? grid.sticks->size() : 0;
  for (const std::uint32_t id : grid.stickId) {
    if (id > stickEntries) {
      throw std::invalid_argument("writeTerrainDatabase: stick id " + std::to_string(id) + " with " +
                                  std::to_string(stickEntries) + " stick table entries");
    }
  }
  if (options.progress) options.progress("pyramid", 0.0);
  const Pyramid pyramid = buildPyramid(g, grid.heightQ, grid.colourRgba, grid.stickId, options.threads);
  if (options.progress) options.progress("pyramid", 1.0);

  // Tiles in index order; compressed in parallel, written in batches so memory stays bounded.
  struct TileRef {
    int level, tx, ty;
  };
  std::vector<TileRef> tiles;
  for (int level = 0; level < g.levels; ++level) {
    for (int ty = 0; ty < g.tilesY(level); ++ty) {
      for (int tx = 0; tx < g.tilesX(level); ++tx) tiles.push_back({level, tx, ty});
    }
  }
  DatabaseWriter writer(path, layout, grid.sticks.get());
  const int threads = detail::resolveThreads(options.threads);
  const std::size_t batch = static_cast<std::size_t>(threads) * 8;
  std::vector<std::vector<std::byte>> compressed(batch);
  for (std::size_t first = 0; first < tiles.size(); first += batch) {
    const std::size_t count = std::min(batch, tiles.size() - first);
    detail::parallelFor(count, threads, 1, [&](std::size_t begin, std::size_t end) {
      thread_local TileBuffers buffers;
      buffers.resize(g.tileShift);
      buffers.stickId.resize(grid.stickId.empty() ? 0 : buffers.heightQ.size());
      for (std::size_t k = begin; k < end; ++k) {
        const TileRef& t = tiles[first + k];
        cutTile(pyramid[static_cast<std::size_t>(t.level)], g.tileShift, t.tx, t.ty, buffers.heightQ,
                buffers.maxHeightQ, buffers.colourRgba, buffers.stickId);
        compressed[k] = encodeTile(buffers, g.tileShift, layout.voxelColour, options.zstdLevel);
      }
    });
    for (std::size_t k = 0; k < count; ++k) {
      const TileRef& t = tiles[first + k];
      writer.writeTile(t.level, t.tx, t.ty, compressed[k]);
    }
    if (options.progress) {
      options.progress("tiles", static_cast<double>(first + count) / static_cast<double>(tiles.size()));
    }
  }
  BuildReport report;
  report.geometry = g;
  report.tileCount = tiles.size();
  report.rawBytes = tiles.size() * rawTileBytes(g.tileShift, layout.voxelColour);
  report.fileBytes = writer.commit();
  return report;
}

}  // namespace fieldcast::core
