// The stick layer: the shared table (mips, colour by depth below the top, its stored form and
// what it refuses), the pyramid carrying sticks up, and version 3 databases round-tripping them
// while version 2 files still open.
#include "TerrainTestUtil.h"

#include <ig_core/MemoryTerrain.h>
#include <ig_core/Sticks.h>
#include <ig_core/TerrainBuilder.h>
#include <ig_core/TerrainDatabase.h>
#include <ig_core/TileCache.h>

#include <gtest/gtest.h>
#include <xxhash.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <string>
#include <vector>

#ifndef FIELDCAST_SOURCE_DIR
#define FIELDCAST_SOURCE_DIR "."
#endif

namespace fieldcast::core {
namespace {

using testing::ScratchDir;

constexpr std::uint32_t grey(std::uint32_t v) { return v | (v << 8) | (v << 16) | 0xFF000000u; }

StickTable twoSticks() {
  // 1: a uniform red hedge of 3 units; 2: a textured stick of 5, grey 10, 20, 30, 40, 50 top down
  return StickTable(0.5, {StickEntry{StickKind::Uniform, 3, {0xFF0000FFu}},
                          StickEntry{StickKind::Textured, 5, {grey(10), grey(20), grey(30), grey(40), grey(50)}}});
}

TEST(StickTable, TexturedSticksAreFilteredTwoToOneUpThePyramid) {
  const StickTable table = twoSticks();
  EXPECT_EQ(table.size(), 2u);
  const auto level0 = table.texels(2, 0);
  EXPECT_EQ(std::vector<std::uint32_t>(level0.begin(), level0.end()),
            (std::vector<std::uint32_t>{grey(10), grey(20), grey(30), grey(40), grey(50)}));
  const auto level1 = table.texels(2, 1);  // pairs, the odd one out alone
  EXPECT_EQ(std::vector<std::uint32_t>(level1.begin(), level1.end()),
            (std::vector<std::uint32_t>{grey(15), grey(35), grey(50)}));
  const auto level2 = table.texels(2, 2);
  EXPECT_EQ(std::vector<std::uint32_t>(level2.begin(), level2.end()), (std::vector<std::uint32_t>{grey(25), grey(50)}));
  EXPECT_EQ(table.texels(2, 3).size(), 1u);
  EXPECT_EQ(table.texels(2, 9).size(), 1u);  // beyond its mips: the last
  EXPECT_EQ(table.texels(1, 0).size(), 1u);  // uniform: one colour at every level
}

TEST(StickTable, AColourIsChosenByDepthBelowTheTopInUnitsOfTheLevel) {
  const StickTable table = twoSticks();
  EXPECT_EQ(table.colourBelowTop(2, 0, 0.0), grey(10));
  EXPECT_EQ(table.colourBelowTop(2, 0, 0.99), grey(10));
  EXPECT_EQ(table.colourBelowTop(2, 0, 1.0), grey(20));
  EXPECT_EQ(table.colourBelowTop(2, 0, 4.5), grey(50));
  EXPECT_EQ(table.colourBelowTop(2, 0, 40.0), grey(50));  // lower ground than the stick was made for
  EXPECT_EQ(table.colourBelowTop(2, 0, -3.0), grey(10));  // above the top (a neighbour's lean)
  EXPECT_EQ(table.colourBelowTop(2, 1, 2.5), grey(35));   // level 1: two units a texel
  EXPECT_EQ(table.colourBelowTop(1, 0, 2.0), 0xFF0000FFu);
}

TEST(StickTable, RoundTripsThroughItsStoredForm) {
  const StickTable table = twoSticks();
  const std::vector<std::byte> bytes = table.serialize();
  EXPECT_EQ(bytes.size(), 16u + 2 * 8 + 4 * 6);
  const StickTable back = StickTable::parse(bytes);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back.unitM(), 0.5);
  for (std::uint32_t id = 1; id <= 2; ++id) {
    EXPECT_EQ(back.entry(id).kind, table.entry(id).kind);
    EXPECT_EQ(back.entry(id).lengthVox, table.entry(id).lengthVox);
    EXPECT_EQ(back.entry(id).texels, table.entry(id).texels);
  }
}

// A complex stick of 6, top down: crown 40, 60 (opaque), two cavities, a half-transparent 100,
// the trunk 120 (opaque)
constexpr std::uint32_t kCavity = 0u;
constexpr std::uint32_t kHalf = (grey(100) & 0x00FFFFFFu) | 0x80000000u;
StickTable crownOverAGap() {
  return StickTable(0.5, {StickEntry{StickKind::Complex, 6, {grey(40), grey(60), kCavity, kCavity, kHalf, grey(120)}}});
}

TEST(StickTable, AComplexStickSeesThroughAtLevelZeroOnlyItsCavitiesFilledAbove) {
  const StickTable table = crownOverAGap();
  EXPECT_TRUE(table.hasSeeThrough());
  EXPECT_FALSE(twoSticks().hasSeeThrough());
  const auto level0 = table.texels(1, 0);
  ASSERT_EQ(level0.size(), 6u);
  EXPECT_EQ(level0[0], grey(40));
  EXPECT_EQ(level0[4], kHalf);
  // A cavity stays see-through, coloured by what fills it: the first texel below that is not one
  EXPECT_EQ(level0[2] >> 24, 0u);
  EXPECT_EQ(level0[2] & 0x00FFFFFFu, grey(100) & 0x00FFFFFFu);
  // Level 1: (40, 60) → 50; (cavity, cavity) → what fills them, 100 below; (half 100, 120) →
  // alpha-weighted 100·128 + 120·255 over 383 = 113; all opaque
  const auto level1 = table.texels(1, 1);
  EXPECT_EQ(std::vector<std::uint32_t>(level1.begin(), level1.end()),
            (std::vector<std::uint32_t>{grey(50), grey(100), grey(113)}));
  for (int level = 1; level < 4; ++level)
    for (const std::uint32_t t : table.texels(1, level)) EXPECT_EQ(t >> 24, 0xFFu) << "level " << level;
  // A textured stick's alpha is not looked at: opaque at every level, whatever it was given
  const StickTable textured(0.5, {StickEntry{StickKind::Textured, 2, {kHalf, kCavity}}});
  for (const std::uint32_t t : textured.texels(1, 0)) EXPECT_EQ(t >> 24, 0xFFu);
  // A complex stick one texel long still has a level 1, filled
  const StickTable one(0.5, {StickEntry{StickKind::Complex, 1, {kHalf}}});
  EXPECT_EQ(one.texels(1, 0)[0], kHalf);
  EXPECT_EQ(one.texels(1, 1)[0], grey(100));
  EXPECT_EQ(one.texels(1, 5)[0], grey(100));
}

TEST(StickTable, AComplexStickRoundTripsWithItsAlpha) {
  const StickTable back = StickTable::parse(crownOverAGap().serialize());
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back.entry(1).kind, StickKind::Complex);
  EXPECT_EQ(back.entry(1).texels, crownOverAGap().entry(1).texels);
  EXPECT_TRUE(back.hasSeeThrough());
}

// The renderers bound how far a stick can rise past a crossing by the longest entry
TEST(StickTable, KnowsItsLongestStick) {
  EXPECT_EQ(twoSticks().longestVox(), 5u);
  EXPECT_EQ(StickTable::parse(twoSticks().serialize()).longestVox(), 5u);
  EXPECT_EQ(crownOverAGap().longestVox(), 6u);
  EXPECT_EQ(StickTable(0.5, {}).longestVox(), 0u);
}

TEST(StickTable, RefusesWhatItCannotHold) {
  auto refuses = [](auto make, const std::string& what) {
    try {
      make();
      ADD_FAILURE() << "accepted: " << what;
    } catch (const StickTableError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  refuses([] { StickTable(0.0, {}); }, "unit of 0");
  refuses([] { StickTable(1e-9, {}); }, "expected 0.001 .. 1000 m");
  refuses([] { StickTable(0.5, {StickEntry{StickKind::Textured, 3, {1, 2}}}); }, "2 colours for a textured stick of 3");
  refuses([] { StickTable(0.5, {StickEntry{StickKind::Complex, 2, {1}}}); }, "1 colours for a complex stick of 2");
  refuses([] { StickTable(0.5, {StickEntry{StickKind::Uniform, 0, {1}}}); }, "length 0");
  refuses([] { StickTable(0.5, {StickEntry{static_cast<StickKind>(9), 1, {1}}}); }, "unknown kind 9");
  const std::vector<std::byte> good = twoSticks().serialize();
  refuses([&] { StickTable::parse(std::span(good).first(10)); }, "its header needs 16");
  refuses([&] { StickTable::parse(std::span(good).first(good.size() - 4)); }, "bytes of colours");
  std::vector<std::byte> many = good;
  const std::uint32_t count = kMaxStickEntries + 1;
  std::memcpy(many.data(), &count, 4);
  refuses([&] { StickTable::parse(many); }, "entries do not fit");
  std::vector<std::byte> kind = good;
  kind[16] = std::byte{7};
  refuses([&] { StickTable::parse(kind); }, "unknown kind 7");
}

// A flat 64 × 64 grid (height 1000 q) with one stick of 200 q at (9, 9) and a 2 × 2 block of
// sticks of 100 q at (20..21, 30..31)
TerrainGrid gridWithSticks() {
  TerrainGrid grid;
  grid.geometry.widthVox = grid.geometry.heightVox = 64;
  grid.geometry.heightStepM = 0.05;
  grid.heightQ.assign(64 * 64, 1000);
  grid.colourRgba.assign(64 * 64, grey(90));
  grid.stickId.assign(64 * 64, 0);
  grid.sticks = std::make_shared<const StickTable>(twoSticks());
  auto at = [](int i, int j) { return static_cast<std::size_t>(j * 64 + i); };
  grid.heightQ[at(9, 9)] = 1200;
  grid.stickId[at(9, 9)] = 2;
  for (int j = 30; j < 32; ++j)
    for (int i = 20; i < 22; ++i) {
      grid.heightQ[at(i, j)] = 1100;
      grid.stickId[at(i, j)] = 1;
    }
  return grid;
}

TEST(StickPyramid, ACoarseVoxelOverAStickTakesItsTopAndId) {
  TerrainGrid grid = gridWithSticks();
  grid.geometry.levels = 4;
  const Pyramid pyramid = buildPyramid(grid.geometry, grid.heightQ, grid.colourRgba, grid.stickId);
  // The lone stick: its top, not a quarter of its height, at every level
  for (int level = 1; level < 4; ++level) {
    const PyramidLevel& l = pyramid[static_cast<std::size_t>(level)];
    const std::size_t o = static_cast<std::size_t>((9 >> level) * l.widthVox + (9 >> level));
    EXPECT_EQ(l.heightQ[o], 1200) << "level " << level;
    EXPECT_EQ(l.stickId[o], 2u) << "level " << level;
  }
  // Plain ground stays the box filter, with no stick
  const PyramidLevel& l1 = pyramid[1];
  EXPECT_EQ(l1.heightQ[static_cast<std::size_t>(2 * l1.widthVox + 2)], 1000);
  EXPECT_EQ(l1.stickId[static_cast<std::size_t>(2 * l1.widthVox + 2)], 0u);
  // Without stick ids the same heights are box-filtered: the lone stick shrinks to a quarter
  const Pyramid plain = buildPyramid(grid.geometry, grid.heightQ, grid.colourRgba);
  EXPECT_EQ(plain[1].heightQ[static_cast<std::size_t>(4 * plain[1].widthVox + 4)], 1050);
  EXPECT_TRUE(plain[1].stickId.empty());
}

TEST(StickPyramid, AStickBelowTheFilteredGroundLeavesTheCoarseVoxelToTheTerrain) {
  // A 2 × 2 block: ground at 1000 and 1000, a steep 1400 beside a hedge of 50 q on 1000: the box
  // filter (1112) stands above the hedge's top, so the coarse voxel is terrain, not hedge
  TerrainGrid grid = gridWithSticks();
  auto at = [](int i, int j) { return static_cast<std::size_t>(j * 64 + i); };
  grid.heightQ[at(40, 40)] = 1050;
  grid.stickId[at(40, 40)] = 1;
  grid.heightQ[at(41, 41)] = 1400;
  grid.geometry.levels = 2;
  const Pyramid pyramid = buildPyramid(grid.geometry, grid.heightQ, grid.colourRgba, grid.stickId);
  const std::size_t o = static_cast<std::size_t>(20 * pyramid[1].widthVox + 20);
  EXPECT_EQ(pyramid[1].heightQ[o], 1113);  // (1050 + 1000 + 1000 + 1400 + 2) / 4
  EXPECT_EQ(pyramid[1].stickId[o], 0u);
}

TEST(StickDatabase, Version3KeepsTheTableAndEveryTilesIds) {
  ScratchDir dir;
  const TerrainGrid grid = gridWithSticks();
  BuildOptions options;
  options.tileShift = 4;  // 16² tiles: sticks in some, none in others
  writeTerrainDatabase(grid, dir / "s.fctdb", options);
  const DatabaseReader reader(dir / "s.fctdb");
  EXPECT_EQ(reader.layout().version, 3u);
  ASSERT_NE(reader.sticks(), nullptr);
  EXPECT_EQ(reader.sticks()->size(), 2u);
  EXPECT_EQ(reader.sticks()->entry(2).texels, grid.sticks->entry(2).texels);
  TileBuffers tile;
  reader.readTile(0, 0, 0, tile);  // voxels 0..15: the lone stick at (9, 9)
  ASSERT_EQ(tile.stickId.size(), 256u);
  EXPECT_EQ(tile.stickId[9 * 16 + 9], 2u);
  EXPECT_EQ(tile.heightQ[9 * 16 + 9], 1200);
  EXPECT_EQ(std::count(tile.stickId.begin(), tile.stickId.end(), 0u), 255);
  reader.readTile(0, 1, 1, tile);  // voxels 16..31: the block at (20..21, 30..31)
  EXPECT_EQ(tile.stickId[14 * 16 + 4], 1u);
  reader.readTile(0, 3, 3, tile);  // no stick: an empty array, as a tile without sticks is kept
  EXPECT_TRUE(tile.stickId.empty());
  reader.readTile(2, 0, 0, tile);  // level 2: the stick carried up
  EXPECT_EQ(tile.stickId[2 * 16 + 2], 2u);
}

// Every voxel's bit in TerrainTile::stickBits (which the caster asks before the id plane) is set
// exactly where its stick id is not 0: in the bits of any id array, and in every tile a terrain
// publishes, from memory and from a database through the tile cache.
TEST(StickTiles, EveryTilesBitsSayWhichOfItsVoxelsHaveAStick) {
  std::vector<std::uint32_t> ids(130, 0);
  for (const std::size_t k : {0u, 5u, 63u, 64u, 127u, 129u}) ids[k] = 7;
  const std::vector<std::uint64_t> bits = stickBitsOf(ids);
  ASSERT_EQ(bits.size(), 3u);
  const TerrainTile tile{nullptr, nullptr, nullptr, ids.data(), bits.data()};
  for (std::size_t k = 0; k < ids.size(); ++k) EXPECT_EQ(tile.hasStick(k), ids[k] != 0) << "voxel " << k;

  const auto checkTiles = [](const TerrainView& view, const char* what) {
    int tilesWithSticks = 0;
    const TerrainGeometry& g = view.geometry();
    for (int level = 0; level < g.levels; ++level)
      for (int ty = 0; ty < g.tilesY(level); ++ty)
        for (int tx = 0; tx < g.tilesX(level); ++tx) {
          const TerrainTile* t = view.tile(level, tx, ty);
          ASSERT_NE(t, nullptr) << what;
          if (t->stickId == nullptr) continue;
          ++tilesWithSticks;
          ASSERT_NE(t->stickBits, nullptr) << what;
          const std::size_t voxels = std::size_t{1} << (2 * g.tileShift);
          for (std::size_t k = 0; k < voxels; ++k)
            ASSERT_EQ(t->hasStick(k), t->stickId[k] != 0)
                << what << ", level " << level << " tile " << tx << ", " << ty;
        }
    EXPECT_GT(tilesWithSticks, 2) << what;
  };
  TerrainGrid grid = gridWithSticks();
  grid.geometry.tileShift = 4;
  grid.geometry.levels = 3;
  const MemoryTerrain memory(grid.geometry, grid.heightQ, grid.colourRgba, grid.stickId, grid.sticks);
  checkTiles(memory.view(), "in memory");

  ScratchDir dir;
  BuildOptions options;
  options.tileShift = 4;
  writeTerrainDatabase(gridWithSticks(), dir / "s.fctdb", options);
  TileCache cache(std::make_unique<DatabaseTileSource>(dir / "s.fctdb"), TileCacheOptions{});
  const TerrainGeometry& g = cache.view().geometry();
  for (int level = 0; level < g.levels; ++level)
    for (int ty = 0; ty < g.tilesY(level); ++ty)
      for (int tx = 0; tx < g.tilesX(level); ++tx) cache.request(level, tx, ty);
  ASSERT_TRUE(cache.waitIdle(std::chrono::seconds(10)));
  checkTiles(cache.view(), "through the tile cache");
}

TEST(StickDatabase, AnIdBeyondTheTableIsACorruptTile) {
  TileBuffers tile;
  tile.resize(4);
  tile.stickId.assign(256, 0);
  tile.stickId[17] = 3;
  const std::vector<std::byte> compressed = encodeTile(tile, 4, VoxelColour::Rgba, 3);
  const TileIndexEntry entry{0, static_cast<std::uint32_t>(compressed.size()),
                             XXH3_64bits(compressed.data(), compressed.size())};
  TileBuffers out;
  decodeTile(compressed, entry, 4, VoxelColour::Rgba, out, "t", TileSticks{true, 3});
  EXPECT_EQ(out.stickId[17], 3u);
  try {
    decodeTile(compressed, entry, 4, VoxelColour::Rgba, out, "t", TileSticks{true, 2});
    FAIL() << "an id beyond a table of 2 decoded";
  } catch (const TerrainDatabaseError& e) {
    EXPECT_NE(std::string(e.what()).find("stick id 3 beyond the stick table's 2 entries"), std::string::npos)
        << e.what();
  }
}

TEST(StickDatabase, AVersion2FileOpensWithNoSticks) {
  // Written by the version 2 code (the fuzzer's seed), byte for byte as it was.
  const std::filesystem::path old =
      std::filesystem::path(FIELDCAST_SOURCE_DIR) / "ig_core" / "terrain" / "fuzz" / "corpus" / "tiny-utm.fctdb";
  const std::vector<char> bytes = testing::readFile(old);
  ASSERT_EQ(bytes[8], 2) << "the seed is no longer a version 2 file";
  const DatabaseReader reader(old);
  EXPECT_EQ(reader.layout().version, 2u);
  EXPECT_EQ(reader.sticks(), nullptr);
  TileBuffers tile;
  reader.readTile(0, 0, 0, tile);
  EXPECT_TRUE(tile.stickId.empty());
  EXPECT_FALSE(tile.heightQ.empty());
}

}  // namespace
}  // namespace fieldcast::core
