// Interop: GeoTIFFs written by GDAL (gdal_translate, the tool most DEMs pass through) import with
// the same heights, spacing, origin and nodata as the ESRI ASCII grid they were made from.
// Skipped when gdal_translate is absent (scripts/install-deps.sh --interop installs gdal-bin).
#include <ig_core/ElevationImport.h>

#include "TerrainTestUtil.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>

namespace fieldcast::core {
namespace {

bool haveGdal() { return std::system("command -v gdal_translate > /dev/null 2>&1") == 0; }

// 41×29 whole-metre heights at 30 m with the lower-left corner at (640000, 5200000), a nodata hole.
void writeAsc(const std::filesystem::path& path) {
  std::ofstream out(path);
  out << "ncols 41\nnrows 29\nxllcorner 640000\nyllcorner 5200000\ncellsize 30\nNODATA_value -9999\n";
  for (int y = 0; y < 29; ++y) {
    for (int x = 0; x < 41; ++x) {
      const bool hole = x >= 20 && x < 24 && y >= 10 && y < 13;
      out << (hole ? -9999 : 300 + 7 * x - 5 * y + (x * y) % 11) << (x < 40 ? " " : "\n");
    }
  }
}

void expectSame(const ElevationGrid& a, const ElevationGrid& b) {
  ASSERT_EQ(a.widthVox, b.widthVox);
  ASSERT_EQ(a.heightVox, b.heightVox);
  EXPECT_DOUBLE_EQ(a.spacingM, b.spacingM);
  EXPECT_NEAR(a.originM.x, b.originM.x, 1e-6);
  EXPECT_NEAR(a.originM.y, b.originM.y, 1e-6);
  EXPECT_EQ(a.nodataFilled, b.nodataFilled);
  for (std::size_t k = 0; k < a.heightsM.size(); ++k) ASSERT_NEAR(a.heightsM[k], b.heightsM[k], 1e-3) << k;
}

class GdalInterop : public ::testing::TestWithParam<std::string> {};

TEST_P(GdalInterop, GeoTiffImportsLikeItsSource) {
  if (!haveGdal()) GTEST_SKIP() << "gdal_translate not found (install gdal-bin: scripts/install-deps.sh --interop)";
  testing::ScratchDir dir;
  writeAsc(dir / "dem.asc");
  const std::string command = "gdal_translate -q -of GTiff -a_srs EPSG:32633 " + GetParam() + " " +
                              (dir / "dem.asc").string() + " " + (dir / "dem.tif").string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const ElevationGrid reference = importElevation(dir / "dem.asc");
  EXPECT_DOUBLE_EQ(reference.originM.x, 640015.0);
  EXPECT_EQ(reference.nodataFilled, 12u);
  const ElevationGrid fromGdal = importElevation(dir / "dem.tif");
  EXPECT_TRUE(fromGdal.spacingFromFile);
  expectSame(fromGdal, reference);
}

INSTANTIATE_TEST_SUITE_P(Layouts, GdalInterop,
                         ::testing::Values("-ot Float32 -co TILED=YES -co COMPRESS=LZW",
                                           "-ot Int16 -co COMPRESS=DEFLATE",
                                           "-ot UInt16 -a_nodata 0 -co TILED=YES -co COMPRESS=NONE",
                                           "-ot Float32 -co COMPRESS=DEFLATE -mo AREA_OR_POINT=Point"));

}  // namespace
}  // namespace fieldcast::core
