#include <ig_core/BuiltinTerrain.h>
#include <ig_core/ObjectModels.h>
#include <ig_core/OpenTerrain.h>

#include "TerrainTestUtil.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <xxhash.h>

#include <algorithm>
#include <map>
#include <string>

namespace fieldcast::core {
namespace {

using testing::ScratchDir;

constexpr int kSize = 512;  // 1 km at 2 m: small enough for a unit test, big enough for every feature

BuiltinTerrainSpec smallSpec(std::uint64_t seed = 1) {
  BuiltinTerrainSpec spec;
  spec.sizeVox = kSize;
  spec.seed = seed;
  return spec;
}

std::uint64_t hashOf(const std::vector<std::uint16_t>& v) { return XXH3_64bits(v.data(), v.size() * 2); }

TEST(BuiltinTerrain, SameSpecSameVoxelsForAnyThreadCount) {
  const BuiltinHeights one = generateBuiltinHeights(smallSpec(), 1);
  const BuiltinHeights two = generateBuiltinHeights(smallSpec(), 2);
  EXPECT_EQ(hashOf(one.heightQ), hashOf(two.heightQ));
  EXPECT_EQ(one.waterDepthM, two.waterDepthM);
  EXPECT_NE(hashOf(generateBuiltinHeights(smallSpec(2), 2).heightQ), hashOf(one.heightQ));
}

TEST(BuiltinTerrain, HasSeaPlainsRiverAndMountains) {
  BuiltinTerrainSpec spec = smallSpec();
  spec.sizeVox = 1024;
  spec.spacingM = 16.0;  // the full 16 km layout at a coarse spacing
  const BuiltinHeights t = generateBuiltinHeights(spec, 2);
  const TerrainGeometry& g = t.geometry;
  const auto heightAt = [&](glm::dvec2 p) {
    const int i = std::clamp(static_cast<int>(std::lround(p.x / g.spacingM)), 0, g.widthVox - 1);
    const int j = std::clamp(static_cast<int>(std::lround(p.y / g.spacingM)), 0, g.heightVox - 1);
    return g.heightM(t.heightQ[static_cast<std::size_t>(j) * g.widthVox + i]);
  };
  const auto waterAt = [&](glm::dvec2 p) {
    const int i = std::clamp(static_cast<int>(std::lround(p.x / g.spacingM)), 0, g.widthVox - 1);
    const int j = std::clamp(static_cast<int>(std::lround(p.y / g.spacingM)), 0, g.heightVox - 1);
    return t.waterDepthM[static_cast<std::size_t>(j) * g.widthVox + i];
  };
  std::size_t water = 0;
  for (const std::uint8_t d : t.waterDepthM) water += d > 0 ? 1 : 0;
  const double waterShare = static_cast<double>(water) / static_cast<double>(t.waterDepthM.size());
  EXPECT_GT(waterShare, 0.08);
  EXPECT_LT(waterShare, 0.30);

  std::map<std::string, BuiltinLandmark> marks;
  for (const BuiltinLandmark& m : builtinLandmarks(spec)) marks[m.name] = m;
  ASSERT_EQ(marks.size(), 14u);
  // The sea in the south, the bay and the river are water; the ridge and mountains are high.
  EXPECT_GT(waterAt({8000.0, 200.0}), 10);
  EXPECT_GT(waterAt(marks["bay"].positionM), 0);
  EXPECT_GT(waterAt(marks["river_plains_bend"].positionM), 0);
  EXPECT_GT(waterAt(marks["valley_mountains"].positionM), 0);
  EXPECT_EQ(waterAt(marks["plains"].positionM), 0);
  EXPECT_GT(heightAt(marks["long_ridge_mid"].positionM), heightAt(marks["plains"].positionM) + 300.0);
  EXPECT_GT(heightAt(marks["island"].positionM), 30.0);
  // The valley is a valley: its floor lies far below the ground 1.5 km to either side.
  const glm::dvec2 valley = marks["valley_mountains"].positionM;
  const double floorM = heightAt(valley);
  EXPECT_LT(floorM + 300.0, heightAt(valley + glm::dvec2(1500.0, 0.0)));
  EXPECT_LT(floorM + 300.0, heightAt(valley + glm::dvec2(-1500.0, 0.0)));
  // The river runs downhill to the sea.
  EXPECT_GT(marks["valley_head"].groundM, marks["valley_mountains"].groundM);
  EXPECT_GT(marks["valley_mountains"].groundM, marks["river_plains_bend"].groundM);
  EXPECT_GT(marks["river_plains_bend"].groundM, marks["river_mouth"].groundM);
  // Mountains reach well above a kilometre.
  EXPECT_GT(*std::max_element(t.heightQ.begin(), t.heightQ.end()) * g.heightStepM + g.heightBaseM, 1200.0);
}

TEST(BuiltinTerrain, IsFurnishedWithWoodsHedgerowsFarmsAndVillages) {
  // 4096² at 2 m (8 km): its lowlands hold villages on the river, farmsteads, woods, hedgerows
  BuiltinTerrainSpec spec{4096, 2.0, 1};
  ProceduralColourOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const TerrainGrid furnished = generateBuiltinTerrain(spec, one);
  ASSERT_NE(furnished.sticks, nullptr);
  ASSERT_EQ(furnished.stickId.size(), furnished.heightQ.size());
  // Which models stand on it: count the voxels of each kind of stick by its top colour
  std::map<std::string, std::size_t> voxelsOf;
  for (const VoxelModel& m : builtinModels()) {
    for (const StickEntry& e : m.sticks) {
      for (std::uint32_t id = 1; id <= furnished.sticks->size(); ++id) {
        if (furnished.sticks->entry(id).texels != e.texels) continue;
        voxelsOf[m.name] +=
            static_cast<std::size_t>(std::count(furnished.stickId.begin(), furnished.stickId.end(), id));
      }
    }
  }
  for (const char* model : {"conifer", "broadleaf", "hedge", "house", "barn", "church"}) {
    EXPECT_GT(voxelsOf[model], 0u) << "no " << model << " on the built-in terrain";
  }
  EXPECT_GT(voxelsOf["hedge"], 10000u);
  EXPECT_GT(voxelsOf["conifer"] + voxelsOf["broadleaf"], 100000u);
  // Deterministic for any thread count; and the bare land has none of it
  const TerrainGrid again = generateBuiltinTerrain(spec, two);
  EXPECT_EQ(again.stickId, furnished.stickId);
  EXPECT_EQ(again.heightQ, furnished.heightQ);
  spec.sizeVox = 1024;
  spec.objects = false;
  const TerrainGrid bare = generateBuiltinTerrain(spec, one);
  EXPECT_TRUE(bare.stickId.empty());
  EXPECT_EQ(bare.sticks, nullptr);
  EXPECT_NE(builtinDatabasePath("c", spec), builtinDatabasePath("c", BuiltinTerrainSpec{1024, 2.0, 1}));
}

TEST(BuiltinTerrain, CacheDirFollowsTheEnvironment) {
  const char* saved = std::getenv("FIELDCAST_CACHE_DIR");
  const std::string keep = saved != nullptr ? saved : "";
  const char* savedHome = std::getenv("HOME");
  const std::string keepHome = savedHome != nullptr ? savedHome : "";
  ::setenv("FIELDCAST_CACHE_DIR", "/tmp/fc-cache-test", 1);
  EXPECT_EQ(defaultCacheDir(), "/tmp/fc-cache-test");
  ::unsetenv("FIELDCAST_CACHE_DIR");
  ::setenv("XDG_CACHE_HOME", "/tmp/xdg", 1);
  EXPECT_EQ(defaultCacheDir(), "/tmp/xdg/fieldcast");
  ::unsetenv("XDG_CACHE_HOME");
  ::setenv("HOME", "/home/pilot", 1);
  EXPECT_EQ(defaultCacheDir(), "/home/pilot/.cache/fieldcast");
  if (saved != nullptr) ::setenv("FIELDCAST_CACHE_DIR", keep.c_str(), 1);
  if (savedHome != nullptr) ::setenv("HOME", keepHome.c_str(), 1);
}

TEST(BuiltinTerrain, GeneratedOnceThenReusedAndRebuiltWhenCorrupt) {
  ScratchDir dir;
  testing::writeFile(dir / "builtin-g0-512-2000mm-seed1.fctdb", {'o', 'l', 'd'});  // an older generator's
  testing::writeFile(dir / "mine.fctdb", {'k', 'e', 'e', 'p'});
  int progressCalls = 0;
  const ProgressFn progress = [&](std::string_view, double) { ++progressCalls; };
  const std::filesystem::path path = ensureBuiltinDatabase(dir.path(), smallSpec(), progress, 2);
  EXPECT_EQ(path, builtinDatabasePath(dir.path(), smallSpec()));
  EXPECT_GT(progressCalls, 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "builtin-g0-512-2000mm-seed1.fctdb"));
  EXPECT_TRUE(std::filesystem::exists(dir / "mine.fctdb"));
  const auto written = std::filesystem::last_write_time(path);

  progressCalls = 0;
  EXPECT_EQ(ensureBuiltinDatabase(dir.path(), smallSpec(), progress, 2), path);
  EXPECT_EQ(progressCalls, 0);  // reused, not rebuilt
  EXPECT_EQ(std::filesystem::last_write_time(path), written);

  testing::writeFile(path, {'b', 'a', 'd'});
  ensureBuiltinDatabase(dir.path(), smallSpec(), progress, 2);
  EXPECT_GT(progressCalls, 0);
  EXPECT_NO_THROW(DatabaseReader{path});
}

TEST(BuiltinTerrain, OpenTerrainServesTheBuiltinTerrain) {
  ScratchDir dir;
  const std::unique_ptr<TileCache> terrain = openTerrain("builtin", dir.path(), 64u << 20, smallSpec());
  const TerrainGrid reference = generateBuiltinTerrain(smallSpec());  // furnished: objects' tops included
  ASSERT_NE(terrain->view().sticks(), nullptr);
  // The whole 512² database fits in the budget: load everything, then compare a few voxels.
  for (int level = 0; level < terrain->geometry().levels; ++level) {
    for (int ty = 0; ty < terrain->geometry().tilesY(level); ++ty) {
      for (int tx = 0; tx < terrain->geometry().tilesX(level); ++tx) terrain->request(level, tx, ty);
    }
  }
  ASSERT_TRUE(terrain->waitIdle(std::chrono::seconds(30)));
  for (int j = 0; j < kSize; j += 37) {
    for (int i = 0; i < kSize; i += 41) {
      EXPECT_EQ(terrain->view().heightQ(0, i, j), reference.heightQ[static_cast<std::size_t>(j) * kSize + i]);
    }
  }
  EXPECT_EQ(terrain->view().missCount(), 0u);
  EXPECT_THROW(openTerrain((dir / "missing.fctdb").string(), dir.path(), 1u << 20), TerrainDatabaseError);
}

}  // namespace
}  // namespace fieldcast::core
