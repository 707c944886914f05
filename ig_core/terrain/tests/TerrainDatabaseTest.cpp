#include <ig_core/MemoryTerrain.h>
#include <ig_core/TerrainBuilder.h>
#include <ig_core/TerrainColour.h>
#include <ig_core/TerrainDatabase.h>

#include "TerrainTestUtil.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <xxhash.h>

#include <cstring>

namespace fieldcast::core {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testing::ScratchDir;

// Expects `fn` to throw TerrainDatabaseError whose message contains every fragment.
template <typename Fn>
void expectDatabaseError(Fn&& fn, const std::vector<std::string>& fragments) {
  try {
    fn();
    FAIL() << "expected TerrainDatabaseError";
  } catch (const TerrainDatabaseError& e) {
    for (const std::string& f : fragments) EXPECT_THAT(e.what(), HasSubstr(f));
  }
}

BuildOptions smallTiles(VoxelColour mode = VoxelColour::Rgba) {
  BuildOptions options;
  options.tileShift = 4;
  options.voxelColour = mode;
  options.threads = 2;
  return options;
}

TEST(TerrainDatabase, RoundTripGivesTheSamePyramidTiles) {
  ScratchDir dir;
  const TerrainGrid grid = testing::randomTerrainGrid(70, 45, 1);
  const BuildReport report = writeTerrainDatabase(grid, dir / "t.fctdb", smallTiles());
  EXPECT_EQ(report.geometry.levels, 4);  // 70 → 35 → 18 → 9 ≤ 16
  EXPECT_EQ(report.fileBytes, std::filesystem::file_size(dir / "t.fctdb"));

  const DatabaseReader reader(dir / "t.fctdb");
  const TerrainGeometry& g = reader.geometry();
  EXPECT_EQ(g.widthVox, 70);
  EXPECT_EQ(g.heightVox, 45);
  EXPECT_EQ(g.originM, grid.geometry.originM);
  EXPECT_EQ(g.heightStepM, 0.1);
  EXPECT_EQ(g.heightBaseM, -20.0);
  EXPECT_EQ(reader.layout().tileCount, report.tileCount);

  const Pyramid pyramid = buildPyramid(g, grid.heightQ, grid.colourRgba);
  TileBuffers expected, actual;
  expected.resize(g.tileShift);
  for (int level = 0; level < g.levels; ++level) {
    for (int ty = 0; ty < g.tilesY(level); ++ty) {
      for (int tx = 0; tx < g.tilesX(level); ++tx) {
        cutTile(pyramid[static_cast<std::size_t>(level)], g.tileShift, tx, ty, expected.heightQ, expected.maxHeightQ,
                expected.colourRgba);
        reader.readTile(level, tx, ty, actual);
        ASSERT_EQ(actual.heightQ, expected.heightQ) << "level " << level;
        ASSERT_EQ(actual.maxHeightQ, expected.maxHeightQ) << "level " << level;
        ASSERT_EQ(actual.colourRgba, expected.colourRgba) << "level " << level;
      }
    }
  }
}

TEST(TerrainDatabase, GreyModeStoresLuma) {
  ScratchDir dir;
  TerrainGrid grid = testing::randomTerrainGrid(20, 20, 2);
  grid.colourRgba.assign(grid.colourRgba.size(), packRgba(200, 100, 50));
  writeTerrainDatabase(grid, dir / "g.fctdb", smallTiles(VoxelColour::Grey));
  const DatabaseReader reader(dir / "g.fctdb");
  EXPECT_EQ(reader.layout().voxelColour, VoxelColour::Grey);
  TileBuffers tile;
  reader.readTile(0, 0, 0, tile);
  const std::uint32_t y = (77u * 200 + 150u * 100 + 29u * 50 + 128u) >> 8;
  EXPECT_EQ(tile.colourRgba[0], packRgba(y, y, y));
}

TEST(TerrainDatabase, QuantisationSpansTheRangeWithARoundStep) {
  const HeightQuantisation q = chooseQuantisation(-12.3, 2400.0);
  EXPECT_EQ(q.baseM, -13.0);
  EXPECT_EQ(q.stepM, 0.05);
  EXPECT_EQ(quantiseHeight(-13.0, q), 0);
  EXPECT_EQ(quantiseHeight(2400.0, q), 48260);
  EXPECT_EQ(chooseQuantisation(0.0, 8848.0).stepM, 0.2);
  EXPECT_EQ(quantiseHeight(1e9, q), 65535);
  EXPECT_THROW(chooseQuantisation(0.0, std::nan("")), std::invalid_argument);
}

TEST(TerrainDatabase, AbandonedWriteLeavesNothingBehind) {
  ScratchDir dir;
  {
    DatabaseLayout layout;
    layout.geometry.widthVox = 32;
    layout.geometry.heightVox = 32;
    layout.geometry.tileShift = 4;
    layout.geometry.levels = 2;
    DatabaseWriter writer(dir / "half.fctdb", layout);
    const std::vector<std::byte> junk(100, std::byte{1});
    writer.writeTile(0, 0, 0, junk);
  }  // destroyed without commit, as if the build had been interrupted
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(TerrainDatabase, CommitReplacesAnExistingFileAtomically) {
  ScratchDir dir;
  testing::writeFile(dir / "t.fctdb", {'o', 'l', 'd'});
  writeTerrainDatabase(testing::randomTerrainGrid(16, 16, 3), dir / "t.fctdb", smallTiles());
  EXPECT_NO_THROW(DatabaseReader{dir / "t.fctdb"});
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1);
}

class CorruptDatabase : public ::testing::Test {
 protected:
  void SetUp() override {
    writeTerrainDatabase(testing::randomTerrainGrid(40, 40, 4), path, smallTiles());
    bytes = testing::readFile(path);
  }
  // Rewrites the header checksum so a test reaches the field checks behind it.
  void fixHeaderChecksum() {
    const std::uint64_t sum = XXH3_64bits(bytes.data(), 120);
    std::memcpy(bytes.data() + 120, &sum, 8);
  }
  template <typename T>
  void poke(std::size_t offset, T value) {
    std::memcpy(bytes.data() + offset, &value, sizeof value);
  }
  ScratchDir dir;
  std::filesystem::path path = dir / "c.fctdb";
  std::vector<char> bytes;
};

TEST_F(CorruptDatabase, MissingFile) {
  expectDatabaseError([&] { DatabaseReader r(dir / "nope.fctdb"); }, {"nope.fctdb", "cannot open"});
}

TEST_F(CorruptDatabase, WrongMagic) {
  bytes[0] = 'X';
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, {"c.fctdb", "wrong magic"});
}

TEST_F(CorruptDatabase, WrongVersion) {
  poke<std::uint32_t>(8, 7);
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, {"c.fctdb", "unsupported database version 7"});
}

TEST_F(CorruptDatabase, TruncatedHeader) {
  bytes.resize(50);
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, {"c.fctdb", "truncated: 50 bytes"});
}

TEST_F(CorruptDatabase, TruncatedTiles) {
  bytes.resize(bytes.size() - 10);
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, {"c.fctdb", "truncated", "the file has"});
}

TEST_F(CorruptDatabase, FlippedHeaderByte) {
  bytes[30] ^= 0x40;
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, {"c.fctdb", "header checksum mismatch"});
}

TEST_F(CorruptDatabase, AbsurdSizeIsRejectedBeforeAnyAllocation) {
  poke<std::uint32_t>(16, 0x7FFFFFFF);
  fixHeaderChecksum();
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, {"c.fctdb", "absurd grid size 2147483647x40"});
}

TEST_F(CorruptDatabase, NonFiniteSpacing) {
  poke<double>(24, std::nan(""));
  fixHeaderChecksum();
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, {"c.fctdb", "spacing"});
}

TEST_F(CorruptDatabase, LevelCountDisagreesWithTheGrid) {
  poke<std::uint32_t>(68, 9);
  fixHeaderChecksum();
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, {"c.fctdb", "level count 9"});
}

TEST_F(CorruptDatabase, CorruptIndex) {
  bytes[128 + 5] ^= 0x01;
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, {"c.fctdb", "index checksum mismatch"});
}

TEST_F(CorruptDatabase, CorruptTileFailsItsChecksumWhenRead) {
  bytes[bytes.size() - 3] ^= 0x10;  // inside the last tile (the top level)
  testing::writeFile(path, bytes);
  const DatabaseReader reader(path);  // header and index are fine
  TileBuffers tile;
  const int top = reader.geometry().levels - 1;
  expectDatabaseError([&] { reader.readTile(top, 0, 0, tile); },
                      {"c.fctdb", "tile L" + std::to_string(top), "checksum"});
  EXPECT_NO_THROW(reader.readTile(0, 0, 0, tile));
}

TEST_F(CorruptDatabase, NotADatabaseAtAll) {
  std::vector<char> text(4000, 'a');
  testing::writeFile(path, text);
  expectDatabaseError([&] { DatabaseReader r(path); }, {"c.fctdb", "not a Fieldcast terrain database"});
}

}  // namespace
}  // namespace fieldcast::core
