// Soak: the full-size built-in terrain (8192² at 2 m) built from scratch through openTerrain into
// a scratch cache, every tile verified, and a long flight over it with a small budget.
#include <ig_core/OpenTerrain.h>

#include "TerrainTestUtil.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <thread>

namespace fieldcast::core {
namespace {

TEST(TerrainSoak, FullSizeBuiltinBuildVerifyAndFly) {
  testing::ScratchDir dir;
  const auto start = std::chrono::steady_clock::now();
  const std::unique_ptr<TileCache> terrain = openTerrain("builtin", dir.path(), 96u << 20);
  const double buildS = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::filesystem::path path = builtinDatabasePath(dir.path(), BuiltinTerrainSpec{});
  std::printf("built-in terrain 8192x8192: built in %.1f s, %.1f MiB\n", buildS,
              static_cast<double>(std::filesystem::file_size(path)) / 1048576.0);

  const DatabaseReader reader(path);
  TileBuffers tile;
  const TerrainGeometry& g = reader.geometry();
  for (int level = 0; level < g.levels; ++level) {
    for (int ty = 0; ty < g.tilesY(level); ++ty) {
      for (int tx = 0; tx < g.tilesX(level); ++tx) ASSERT_NO_THROW(reader.readTile(level, tx, ty, tile));
    }
  }
  // Fly east at 300 m/s for 60 s, weaving north and south, frames paced at 60 Hz in real time.
  const Intrinsics camera = Intrinsics::fromHorizontalFov(1024, 768, radians(60.0));
  const auto t0 = std::chrono::steady_clock::now();
  for (int frame = 0; frame < 3600; ++frame) {
    std::this_thread::sleep_until(t0 + std::chrono::microseconds(frame * 16667));
    const double s = frame / 60.0 * 300.0;
    const double along = std::fmod(s, 8000.0);
    Pose pose;
    pose.positionM = {4000.0 + along, 4000.0 + 2000.0 * std::sin(s / 3000.0), 0.0};
    pose.positionM.z = terrain->heightAtM(pose.positionM.x, pose.positionM.y) + 150.0;
    pose.headingRad = radians(90.0);
    pose.pitchRad = radians(-10.0);
    const FrameLease lease = terrain->lease();
    terrain->prefetch(pose, {300.0, 0.0, 0.0}, camera);
    ASSERT_TRUE(std::isfinite(terrain->heightAtM(pose.positionM.x + 500.0, pose.positionM.y)));
    ASSERT_LE(terrain->stats().residentBytes, 96u << 20);
  }
  const TileCacheStats s = terrain->stats();
  std::printf("flight: hit rate %.3f, %llu loads, %llu evictions, %llu failures\n", s.prefetchHitRate,
              static_cast<unsigned long long>(s.loads), static_cast<unsigned long long>(s.evictions),
              static_cast<unsigned long long>(s.loadFailures));
  EXPECT_EQ(s.loadFailures, 0u);
  // 0.993 when last run (a 96 MiB budget holds this flight's requests; ig_core/README.md, Figures,
  // has the paging figures of a flight under 128 and 48 MiB)
  EXPECT_GT(s.requestedTiles, 0u);
  EXPECT_GE(s.prefetchHitRate, 0.85) << s.requestedResident << " of " << s.requestedTiles
                                     << " requested tiles resident";
}

}  // namespace
}  // namespace fieldcast::core
