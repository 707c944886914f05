// Database format version 2 keeps the georeference (the CRS text after the tile index, under the
// index checksum); version 1 files, written before it existed, still open with no georeference.
#include <ig_core/Georeference.h>
#include <ig_core/TerrainBuilder.h>
#include <ig_core/TerrainDatabase.h>
#include <ig_core/TileCache.h>

#include "TerrainTestUtil.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <xxhash.h>

#include <cstring>

namespace fieldcast::core {
namespace {

using ::testing::HasSubstr;
using testing::ScratchDir;

BuildOptions smallTiles() {
  BuildOptions options;
  options.tileShift = 4;
  options.threads = 1;
  return options;
}

template <typename Fn>
void expectDatabaseError(Fn&& fn, const std::string& fragment) {
  try {
    fn();
    FAIL() << "expected TerrainDatabaseError with '" << fragment << "'";
  } catch (const TerrainDatabaseError& e) {
    EXPECT_THAT(e.what(), HasSubstr(fragment));
  }
}

void expectTilesDecode(const DatabaseReader& reader) {
  TileBuffers tile;
  const TerrainGeometry& g = reader.geometry();
  for (int level = 0; level < g.levels; ++level) {
    for (int ty = 0; ty < g.tilesY(level); ++ty) {
      for (int tx = 0; tx < g.tilesX(level); ++tx) ASSERT_NO_THROW(reader.readTile(level, tx, ty, tile));
    }
  }
}

TEST(DatabaseGeoreference, TheCrsRoundTripsInTheCurrentVersion) {
  ScratchDir dir;
  // A long, WKT-like CRS: the length is not limited to anything the header could hold.
  std::string wkt = "PROJCRS[\"Local transverse Mercator at 50.000000, 8.000000\",";
  while (wkt.size() < 3000) wkt += "PARAMETER[\"x\",1,LENGTHUNIT[\"metre\",1]],";
  wkt += "]";
  for (const std::string& crs : {std::string("EPSG:32633"), wkt, std::string()}) {
    TerrainGrid grid = testing::randomTerrainGrid(40, 24, 7);
    grid.crs = crs;
    const BuildReport report = writeTerrainDatabase(grid, dir / "g.fctdb", smallTiles());
    const DatabaseReader reader(dir / "g.fctdb");
    EXPECT_EQ(reader.layout().version, kDatabaseVersion);
    EXPECT_EQ(reader.layout().crs, crs);
    EXPECT_EQ(reader.geometry().originM, grid.geometry.originM);
    EXPECT_EQ(reader.geometry().spacingM, grid.geometry.spacingM);
    EXPECT_EQ(report.fileBytes, std::filesystem::file_size(dir / "g.fctdb"));
    expectTilesDecode(reader);
  }
}

TEST(DatabaseGeoreference, AVersion1FileOpensWithNoGeoreference) {
  // Written by the version 1 code (the fuzzer's seed), byte for byte as it was.
  const std::filesystem::path old =
      std::filesystem::path(FIELDCAST_SOURCE_DIR) / "ig_core" / "terrain" / "fuzz" / "corpus" / "tiny.fctdb";
  const std::vector<char> bytes = testing::readFile(old);
  ASSERT_EQ(bytes[8], 1) << "the seed is no longer a version 1 file";
  const DatabaseReader reader(old);
  EXPECT_EQ(reader.layout().version, 1u);
  EXPECT_TRUE(reader.layout().crs.empty());
  expectTilesDecode(reader);
}

TEST(DatabaseGeoreference, AnOpenTerrainHandsItsCrsToTheGeoreference) {
  ScratchDir dir;
  TerrainGrid grid = testing::randomTerrainGrid(40, 24, 7);
  grid.crs = "EPSG:32633";
  writeTerrainDatabase(grid, dir / "utm.fctdb", smallTiles());
  grid.crs.clear();
  writeTerrainDatabase(grid, dir / "none.fctdb", smallTiles());
  const TileCache utm(std::make_unique<DatabaseTileSource>(dir / "utm.fctdb"), TileCacheOptions{});
  EXPECT_EQ(utm.crs(), "EPSG:32633");
  EXPECT_TRUE(Georeference::forTerrain(utm.crs()).hasCrs());
  const TileCache none(std::make_unique<DatabaseTileSource>(dir / "none.fctdb"), TileCacheOptions{});
  EXPECT_EQ(none.crs(), "");
  EXPECT_FALSE(Georeference::forTerrain(none.crs()).hasCrs());
}

class CorruptGeoreference : public ::testing::Test {
 protected:
  void SetUp() override {
    TerrainGrid grid = testing::randomTerrainGrid(20, 20, 3);
    grid.crs = "EPSG:32633";
    writeTerrainDatabase(grid, path, smallTiles());
    bytes = testing::readFile(path);
    std::uint64_t tiles = 0;
    std::memcpy(&tiles, bytes.data() + 80, 8);
    georeferenceAt = 128 + tiles * 24;
    ASSERT_EQ(std::string(bytes.data() + georeferenceAt, 10), "EPSG:32633");
  }
  // Repairs both checksums so a test reaches the checks behind them.
  void fixChecksums(std::size_t coveredBytes) {
    const std::uint64_t index = XXH3_64bits(bytes.data() + 128, coveredBytes);
    std::memcpy(bytes.data() + 96, &index, 8);
    const std::uint64_t header = XXH3_64bits(bytes.data(), 120);
    std::memcpy(bytes.data() + 120, &header, 8);
  }
  ScratchDir dir;
  std::filesystem::path path = dir / "c.fctdb";
  std::vector<char> bytes;
  std::size_t georeferenceAt = 0;
};

TEST_F(CorruptGeoreference, AFlippedByteFailsTheChecksum) {
  bytes[georeferenceAt + 6] ^= 0x01;
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, "checksum mismatch");
}

TEST_F(CorruptGeoreference, ALengthPastTheFileIsRefusedBeforeReading) {
  const std::uint32_t huge = 60000;
  std::memcpy(bytes.data() + 112, &huge, 4);
  fixChecksums(georeferenceAt - 128 + 10);
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, "georeference of 60000 bytes does not fit in the file");
  const std::uint32_t absurd = 0x7FFFFFFF;
  std::memcpy(bytes.data() + 112, &absurd, 4);
  fixChecksums(georeferenceAt - 128 + 10);
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, "georeference of 2147483647 bytes (at most 65536)");
}

TEST_F(CorruptGeoreference, AControlCharacterIsRefused) {
  bytes[georeferenceAt + 4] = '\0';
  fixChecksums(georeferenceAt - 128 + 10);
  testing::writeFile(path, bytes);
  expectDatabaseError([&] { DatabaseReader r(path); }, "control character at byte 4");
}

TEST(DatabaseGeoreference, TheWriterRefusesACrsTheReaderWouldRefuse) {
  ScratchDir dir;
  TerrainGrid grid = testing::randomTerrainGrid(20, 20, 3);
  grid.crs = "EPSG:\n32633";
  expectDatabaseError([&] { writeTerrainDatabase(grid, dir / "w.fctdb", smallTiles()); }, "control character");
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace fieldcast::core
