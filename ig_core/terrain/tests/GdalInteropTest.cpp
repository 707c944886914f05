// Interop: GeoTIFFs written by GDAL (gdal_translate, the tool most DEMs pass through) import with
// the same heights, spacing, origin and nodata as the ESRI ASCII grid they were made from; a
// GDAL file cut short is refused; a grid in degrees is reprojected as gdalwarp reprojects it.
// Skipped when gdal_translate is absent (scripts/install-deps.sh --interop installs gdal-bin).
#include <ig_core/ElevationImport.h>
#include <ig_core/Georeference.h>

#include "TerrainTestUtil.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace fieldcast::core {
namespace {

bool haveGdal() { return std::system("command -v gdal_translate > /dev/null 2>&1") == 0; }

// Runs a GDAL command line; false when it fails.
bool run(const std::string& command) { return std::system((command + " > /dev/null 2>&1").c_str()) == 0; }

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

class GdalTruncated : public ::testing::TestWithParam<std::string> {};

// GDAL writes the directory first and the strips after it, so a cut keeps the directory and loses
// strips: OpenImageIO would read them as zeros.
TEST_P(GdalTruncated, AStripedFileCutShortIsRefused) {
  if (!haveGdal()) GTEST_SKIP() << "gdal_translate not found (install gdal-bin: scripts/install-deps.sh --interop)";
  testing::ScratchDir dir;
  writeAsc(dir / "dem.asc");
  const std::string command = "gdal_translate -q -of GTiff -a_srs EPSG:32633 -ot Int16 -co BLOCKYSIZE=4 " + GetParam() +
                              " " + (dir / "dem.asc").string() + " " + (dir / "dem.tif").string();
  ASSERT_TRUE(run(command)) << command;
  std::vector<char> bytes = testing::readFile(dir / "dem.tif");
  bytes.resize(bytes.size() * 2 / 3);
  testing::writeFile(dir / "cut.tif", bytes);
  try {
    importElevation(dir / "cut.tif");
    FAIL() << "a cut GeoTIFF imported";
  } catch (const ImportError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("cut.tif: cut short"));
  }
}

INSTANTIATE_TEST_SUITE_P(Compressions, GdalTruncated, ::testing::Values("-co COMPRESS=LZW", "-co COMPRESS=DEFLATE"));

// Reads an ESRI ASCII grid as written by GDAL: W×H values, first row north.
std::vector<double> readAscValues(const std::filesystem::path& path, int& w, int& h) {
  std::ifstream in(path);
  std::string key;
  double value = 0.0;
  for (int k = 0; k < 6 && in >> key >> value; ++k) {
    if (key == "ncols") w = static_cast<int>(value);
    if (key == "nrows") h = static_cast<int>(value);
    if (key == "NODATA_value") break;
  }
  std::vector<double> values;
  while (in >> value) values.push_back(value);
  return values;
}

TEST(GdalInterop, AGridInDegreesIsReprojectedAsGdalwarpDoesIt) {
  if (!haveGdal() || !run("command -v gdalwarp")) GTEST_SKIP() << "gdal_translate/gdalwarp not found (gdal-bin)";
  testing::ScratchDir dir;
  {
    // 60 × 40 heights at 3 arc-seconds, no holes. Linear, so bilinear sampling reproduces it
    // exactly and a difference is a position error: 0.01 pixel is 0.07 m here.
    std::ofstream out(dir / "deg.asc");
    out << "ncols 60\nnrows 40\nxllcorner 8\nyllcorner 50\ncellsize 0.000833333333333333\n";
    for (int y = 0; y < 40; ++y) {
      for (int x = 0; x < 60; ++x) out << 300 + 7 * x - 5 * y << (x < 59 ? " " : "\n");
    }
  }
  ASSERT_TRUE(run("gdal_translate -q -of GTiff -a_srs EPSG:4326 -ot Float32 -co COMPRESS=DEFLATE " +
                  (dir / "deg.asc").string() + " " + (dir / "deg.tif").string()));
  const ElevationGrid ours = importElevation(dir / "deg.tif");
  ASSERT_FALSE(ours.crs.empty());
  EXPECT_TRUE(Georeference::fromCrs(ours.crs).hasCrs());
  std::ofstream(dir / "crs.wkt") << ours.crs;
  // gdalwarp onto our grid subdivided 3 × 3 (pixel (3i + 1, 3j + 1) is centred on our voxel (i, j)):
  // same CRS and extent, bilinear sampling, exact transforms. Finer than the source on both axes,
  // so gdalwarp samples plainly bilinearly (shrinking an axis, it widens its kernel instead).
  const double s = ours.spacingM;
  constexpr int kSub = 3;
  std::ostringstream command;
  command.precision(17);
  command << "gdalwarp -q -overwrite -t_srs " << (dir / "crs.wkt").string() << " -te " << ours.originM.x - 0.5 * s
          << " " << ours.originM.y - 0.5 * s << " " << ours.originM.x + (ours.widthVox - 0.5) * s << " "
          << ours.originM.y + (ours.heightVox - 0.5) * s << " -ts " << kSub * ours.widthVox << " "
          << kSub * ours.heightVox << " -r bilinear -et 0 -dstnodata -9999 -of AAIGrid " << (dir / "deg.tif").string()
          << " " << (dir / "warped.asc").string();
  ASSERT_TRUE(run(command.str())) << command.str();
  int w = 0, h = 0;
  const std::vector<double> warped = readAscValues(dir / "warped.asc", w, h);
  ASSERT_EQ(w, kSub * ours.widthVox);
  ASSERT_EQ(h, kSub * ours.heightVox);
  ASSERT_EQ(warped.size(), static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  // GDAL pixel (x, y), y counted from the south like our rows.
  const auto gdalAt = [&](int x, int y) { return warped[static_cast<std::size_t>(h - 1 - y) * w + x]; };
  // Compared away from the edges, where the two treat the last half pixel differently.
  int compared = 0;
  double worst = 0.0;
  for (int j = 1; j < ours.heightVox - 1; ++j) {
    for (int i = 1; i < ours.widthVox - 1; ++i) {
      bool nearEdge = false;
      for (int dy = -4; dy <= 4; ++dy) {
        for (int dx = -4; dx <= 4; ++dx) nearEdge = nearEdge || gdalAt(kSub * i + 1 + dx, kSub * j + 1 + dy) == -9999.0;
      }
      if (nearEdge) continue;
      const double ourHeight = ours.heightsM[static_cast<std::size_t>(j) * ours.widthVox + i];
      worst = std::max(worst, std::fabs(ourHeight - gdalAt(kSub * i + 1, kSub * j + 1)));
      ++compared;
    }
  }
  EXPECT_GT(compared, ours.widthVox * ours.heightVox / 2);
  std::printf("largest difference from gdalwarp: %.4f m over %d voxels\n", worst, compared);
  EXPECT_LT(worst, 0.02);
}

}  // namespace
}  // namespace fieldcast::core
