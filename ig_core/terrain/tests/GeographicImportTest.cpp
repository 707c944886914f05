// GeoTIFFs keep their georeference: a projected grid its EPSG code and origin; a grid in
// geographic degrees is reprojected onto square metric voxels of its true size (issue 23 item 2:
// it used to become square voxels of the geometric-mean spacing, 1.5× too wide at 50° N, at 0, 0).
// The files are written here with libtiff; the expected sizes come from the ellipsoid's formulas.
#include <ig_core/ElevationImport.h>
#include <ig_core/Georeference.h>

#include "TerrainTestUtil.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tiffio.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

namespace fieldcast::core {
namespace {

using ::testing::HasSubstr;
using testing::ScratchDir;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kA = 6378137.0;
constexpr double kE2 = (1.0 / 298.257223563) * (2.0 - 1.0 / 298.257223563);

// GeoKeyDirectory entries: model type (1 projected, 2 geographic), then the CRS code key.
constexpr std::uint16_t kModelType = 1024, kGeographicType = 2048, kProjectedType = 3072;

struct GeoTiff {
  int width = 48;
  int height = 36;
  double west = 8.0;  // CRS position of the corner of pixel (0, 0)
  double north = 50.03;
  double stepX = 1.0 / 1200.0;  // 3 arc-seconds, as SRTM
  double stepY = 1.0 / 1200.0;
  std::vector<std::uint16_t> keys{kModelType, 0, 1, 2, kGeographicType, 0, 1, 4326};
  // Metres at a CRS position: linear, so bilinear resampling reproduces it exactly.
  std::function<double(double x, double y)> heightAt = [](double lon, double lat) {
    return 200.0 + 4000.0 * (lon - 8.0) + 3000.0 * (50.03 - lat);
  };
};

void writeGeoTiff(const std::filesystem::path& path, const GeoTiff& g) {
  TIFF* tif = TIFFOpen(path.c_str(), "w");
  ASSERT_NE(tif, nullptr);
  static const TIFFFieldInfo kFields[] = {
      {33550, -1, -1, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelPixelScaleTag")},
      {33922, -1, -1, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelTiepointTag")},
      {34735, -1, -1, TIFF_SHORT, FIELD_CUSTOM, 1, 1, const_cast<char*>("GeoKeyDirectoryTag")},
  };
  TIFFMergeFieldInfo(tif, kFields, 3);
  TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, g.width);
  TIFFSetField(tif, TIFFTAG_IMAGELENGTH, g.height);
  TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 32);
  TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_IEEEFP);
  TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
  TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, 8);
  const double scale[3] = {g.stepX, g.stepY, 0.0};
  TIFFSetField(tif, 33550, 3, scale);
  const double tie[6] = {0.0, 0.0, 0.0, g.west, g.north, 0.0};
  TIFFSetField(tif, 33922, 6, tie);
  std::vector<std::uint16_t> directory{1, 1, 0, static_cast<std::uint16_t>(g.keys.size() / 4)};
  directory.insert(directory.end(), g.keys.begin(), g.keys.end());
  TIFFSetField(tif, 34735, static_cast<int>(directory.size()), directory.data());
  std::vector<float> row(static_cast<std::size_t>(g.width));
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      row[static_cast<std::size_t>(x)] =
          static_cast<float>(g.heightAt(g.west + (x + 0.5) * g.stepX, g.north - (y + 0.5) * g.stepY));
    }
    ASSERT_EQ(TIFFWriteScanline(tif, row.data(), static_cast<std::uint32_t>(y), 0), 1);
  }
  TIFFClose(tif);
}

// Metres per degree east and north at latitude `latDeg` on WGS 84.
double metresPerDegreeEast(double latDeg) {
  const double s = std::sin(latDeg * kDeg);
  return kDeg * kA * std::cos(latDeg * kDeg) / std::sqrt(1.0 - kE2 * s * s);
}
double metresPerDegreeNorth(double latDeg) {
  const double s = std::sin(latDeg * kDeg);
  return kDeg * kA * (1.0 - kE2) / std::pow(1.0 - kE2 * s * s, 1.5);
}

TEST(GeographicImport, DegreesBecomeSquareVoxelsOfTheTrueSize) {
  ScratchDir dir;
  const GeoTiff spec;
  writeGeoTiff(dir / "srtm.tif", spec);
  const ElevationGrid g = importElevation(dir / "srtm.tif");
  ASSERT_FALSE(g.crs.empty()) << "the georeference was dropped";
  const double centreLat = spec.north - 0.5 * spec.height * spec.stepY;
  const double dx = spec.stepX * metresPerDegreeEast(centreLat);   // 59.6 m
  const double dy = spec.stepY * metresPerDegreeNorth(centreLat);  // 92.7 m
  EXPECT_NEAR(g.spacingM, std::sqrt(dx * dy), 1e-3 * g.spacingM);
  EXPECT_TRUE(g.spacingFromFile);
  // The grid covers the ground the file covers: 48 × 59.6 m by 36 × 92.7 m, not 48 × 36 squares.
  EXPECT_NEAR((g.widthVox - 1) * g.spacingM, (spec.width - 1) * dx, 1.5 * g.spacingM);
  EXPECT_NEAR((g.heightVox - 1) * g.spacingM, (spec.height - 1) * dy, 1.5 * g.spacingM);
}

TEST(GeographicImport, EveryVoxelHoldsTheHeightOfItsOwnLatitudeAndLongitude) {
  ScratchDir dir;
  const GeoTiff spec;
  writeGeoTiff(dir / "srtm.tif", spec);
  const ElevationGrid g = importElevation(dir / "srtm.tif");
  ASSERT_FALSE(g.crs.empty());
  const Georeference geo = Georeference::fromCrs(g.crs);
  EXPECT_THAT(geo.description(), HasSubstr("Local transverse Mercator at 50.015000, 8.020000 on WGS 84"));
  int inside = 0;
  for (int j = 0; j < g.heightVox; ++j) {
    for (int i = 0; i < g.widthVox; ++i) {
      const glm::dvec3 world(g.originM.x + i * g.spacingM, g.originM.y + j * g.spacingM, 0.0);
      const GeodeticPosition p = *geo.toGeodetic(world);
      // Within the outer ring of pixel centres, where the voxel is resampled rather than filled.
      const bool interior = p.longitudeDeg > spec.west + 0.5 * spec.stepX &&
                            p.longitudeDeg < spec.west + (spec.width - 0.5) * spec.stepX &&
                            p.latitudeDeg < spec.north - 0.5 * spec.stepY &&
                            p.latitudeDeg > spec.north - (spec.height - 0.5) * spec.stepY;
      if (!interior) continue;
      ++inside;
      ASSERT_NEAR(g.heightsM[static_cast<std::size_t>(j) * g.widthVox + i],
                  spec.heightAt(p.longitudeDeg, p.latitudeDeg), 0.01)
          << "voxel " << i << ", " << j << " at " << p.latitudeDeg << " N " << p.longitudeDeg << " E";
    }
  }
  EXPECT_GT(inside, g.widthVox * g.heightVox * 8 / 10);
  // Only the slivers the rotated edges leave at the corners are filled.
  EXPECT_LT(g.nodataFilled, static_cast<std::size_t>(g.widthVox * g.heightVox / 10));
}

TEST(GeographicImport, AProjectedGridKeepsItsEpsgCodeAndOrigin) {
  ScratchDir dir;
  GeoTiff spec;
  spec.west = 500000.0;
  spec.north = 5540000.0;
  spec.stepX = spec.stepY = 25.0;
  spec.keys = {kModelType, 0, 1, 1, kProjectedType, 0, 1, 32632};
  spec.heightAt = [](double x, double y) { return 100.0 + 0.01 * (x - 500000.0) + 0.02 * (5540000.0 - y); };
  writeGeoTiff(dir / "utm.tif", spec);
  const ElevationGrid g = importElevation(dir / "utm.tif");
  EXPECT_EQ(g.crs, "EPSG:32632");
  EXPECT_EQ(g.spacingM, 25.0);
  EXPECT_EQ(g.originM, glm::dvec2(500012.5, 5540000.0 - 35.5 * 25.0));
  // A user-defined CRS (code 32767) is not kept: the grid imports without a georeference.
  spec.keys = {kModelType, 0, 1, 1, kProjectedType, 0, 1, 32767};
  writeGeoTiff(dir / "custom.tif", spec);
  EXPECT_TRUE(importElevation(dir / "custom.tif").crs.empty());
}

TEST(GeographicImport, AGivenSpacingDropsTheGeoreferenceItNoLongerFits) {
  ScratchDir dir;
  writeGeoTiff(dir / "srtm.tif", GeoTiff{});
  ImportOptions options;
  options.spacingM = 30.0;
  const ElevationGrid g = importElevation(dir / "srtm.tif", options);
  EXPECT_EQ(g.spacingM, 30.0);
  EXPECT_TRUE(g.crs.empty());
}

TEST(GeographicImport, AnotherDatumIsKeptAndAnUnknownCodeIsRefused) {
  ScratchDir dir;
  GeoTiff spec;
  spec.keys = {kModelType, 0, 1, 2, kGeographicType, 0, 1, 4258};  // ETRS89: another datum is fine
  writeGeoTiff(dir / "etrs.tif", spec);
  const ElevationGrid g = importElevation(dir / "etrs.tif");
  EXPECT_THAT(Georeference::fromCrs(g.crs).description(), HasSubstr("on ETRS89"));
  spec.keys = {kModelType, 0, 1, 2, kGeographicType, 0, 1, 9999};  // not a geographic CRS
  writeGeoTiff(dir / "bad.tif", spec);
  EXPECT_THROW(importElevation(dir / "bad.tif"), ImportError);
}

}  // namespace
}  // namespace fieldcast::core
