// Import of every elevation format from small files written here: TIFFs by OpenImageIO (every
// sample type, striped/tiled, none/LZW/Deflate), GeoTIFFs by libtiff with georeferencing tags and
// GDAL_NODATA, a 16-bit PNG, ESRI ASCII grids and raw grids with a sidecar, all written by hand.
#include <ig_core/ElevationImport.h>
#include <ig_core/TerrainColour.h>
#include <ig_core/TerrainDatabase.h>

#include "TerrainTestUtil.h"

#include <OpenImageIO/imageio.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tiffio.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <tuple>

namespace fieldcast::core {
namespace {

using ::testing::HasSubstr;
using testing::ScratchDir;

constexpr int kW = 37;
constexpr int kH = 23;

// Value of file pixel (x, y), y counted from the top (north) row.
double truth(int x, int y) { return 100.0 + 3.0 * x - 2.0 * y + ((x * y) % 7); }

template <typename Fn>
void expectImportError(Fn&& fn, const std::vector<std::string>& fragments) {
  try {
    fn();
    FAIL() << "expected ImportError";
  } catch (const ImportError& e) {
    for (const std::string& f : fragments) EXPECT_THAT(e.what(), HasSubstr(f));
  }
}

// Grid voxel (i, j), j counted from the south, holds file pixel (i, H − 1 − j).
void expectMatchesTruth(const ElevationGrid& g, double tolerance = 1e-4) {
  ASSERT_EQ(g.widthVox, kW);
  ASSERT_EQ(g.heightVox, kH);
  for (int j = 0; j < kH; ++j) {
    for (int i = 0; i < kW; ++i) {
      ASSERT_NEAR(g.heightsM[static_cast<std::size_t>(j) * kW + i], truth(i, kH - 1 - j), tolerance)
          << "voxel " << i << ", " << j;
    }
  }
}

template <typename T>
std::vector<T> truthPixels() {
  std::vector<T> pixels;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) pixels.push_back(static_cast<T>(truth(x, y)));
  }
  return pixels;
}

// ---------------------------------------------------------------------------------------------
// TIFF written by OpenImageIO: every sample type, layout and compression.

using TiffCase = std::tuple<std::string, bool, std::string>;  // type, tiled, compression
class TiffImport : public ::testing::TestWithParam<TiffCase> {};

TEST_P(TiffImport, ReadsBackEveryHeight) {
  const auto& [type, tiled, compression] = GetParam();
  ScratchDir dir;
  const std::filesystem::path path = dir / "dem.tif";
  const OIIO::TypeDesc format = type == "int16"    ? OIIO::TypeDesc::INT16
                                : type == "uint16" ? OIIO::TypeDesc::UINT16
                                                   : OIIO::TypeDesc::FLOAT;
  OIIO::ImageSpec spec(kW, kH, 1, format);
  spec.attribute("compression", compression);
  if (tiled) {
    spec.tile_width = 16;
    spec.tile_height = 16;
  }
  // Native samples: OpenImageIO would normalise floats into an integer format's 0..1 range.
  const std::vector<std::int16_t> i16 = truthPixels<std::int16_t>();
  const std::vector<std::uint16_t> u16 = truthPixels<std::uint16_t>();
  const std::vector<float> f32 = truthPixels<float>();
  const void* pixels = type == "int16"    ? static_cast<const void*>(i16.data())
                       : type == "uint16" ? static_cast<const void*>(u16.data())
                                          : static_cast<const void*>(f32.data());
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path.string(), spec));
  ASSERT_TRUE(out->write_image(format, pixels));
  ASSERT_TRUE(out->close());
  // Check the file really has the layout asked for.
  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().tile_width, tiled ? 16 : 0);
  EXPECT_EQ(in->spec().get_string_attribute("compression"), compression);
  EXPECT_EQ(in->spec().format, format);
  in->close();

  ImportOptions options;
  options.spacingM = 5.0;
  const ElevationGrid g = importElevation(path, options);
  expectMatchesTruth(g);
  EXPECT_EQ(g.spacingM, 5.0);
  EXPECT_EQ(g.nodataFilled, 0u);
}

INSTANTIATE_TEST_SUITE_P(EveryLayout, TiffImport,
                         ::testing::Combine(::testing::Values("int16", "uint16", "float32"), ::testing::Bool(),
                                            ::testing::Values("none", "lzw", "zip")),
                         [](const ::testing::TestParamInfo<TiffCase>& p) {
                           return std::get<0>(p.param) + (std::get<1>(p.param) ? "_tiled_" : "_striped_") +
                                  std::get<2>(p.param);
                         });

// ---------------------------------------------------------------------------------------------
// GeoTIFF written by libtiff with georeferencing tags and GDAL_NODATA.

void registerGeoTiffTags(TIFF* tif) {
  static const TIFFFieldInfo kFields[] = {
      {33550, -1, -1, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelPixelScaleTag")},
      {33922, -1, -1, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelTiepointTag")},
      {34735, -1, -1, TIFF_SHORT, FIELD_CUSTOM, 1, 1, const_cast<char*>("GeoKeyDirectoryTag")},
      {42113, -1, -1, TIFF_ASCII, FIELD_CUSTOM, 1, 0, const_cast<char*>("GDALNoDataValue")},
  };
  TIFFMergeFieldInfo(tif, kFields, 4);
}

struct GeoTiffSpec {
  std::uint16_t sampleFormat = SAMPLEFORMAT_IEEEFP;
  std::uint16_t bits = 32;
  std::uint16_t compression = COMPRESSION_ADOBE_DEFLATE;
  bool tiled = true;
  bool pixelIsPoint = false;
  const char* nodata = "-9999";
  double hole = -9999.0;  ///< the value written in the hole
};

// Writes truth() as a GeoTIFF: 10 m pixels, top-left corner at (500000, 4100000), with a 3×3
// nodata hole at file pixels x 10..12, y 5..7.
void writeGeoTiff(const std::filesystem::path& path, const GeoTiffSpec& s) {
  TIFF* tif = TIFFOpen(path.c_str(), "w");
  ASSERT_NE(tif, nullptr);
  registerGeoTiffTags(tif);
  TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, kW);
  TIFFSetField(tif, TIFFTAG_IMAGELENGTH, kH);
  TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, s.bits);
  TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, s.sampleFormat);
  TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tif, TIFFTAG_COMPRESSION, s.compression);
  const double scale[3] = {10.0, 10.0, 0.0};
  TIFFSetField(tif, 33550, 3, scale);
  const double tie[6] = {0.0, 0.0, 0.0, 500000.0, 4100000.0, 0.0};
  TIFFSetField(tif, 33922, 6, tie);
  const std::uint16_t keys[] = {1, 1, 0,    2, 1024, 0,
                                1, 1, 1025, 0, 1,    static_cast<std::uint16_t>(s.pixelIsPoint ? 2 : 1)};
  TIFFSetField(tif, 34735, 12, keys);
  if (s.nodata != nullptr) TIFFSetField(tif, 42113, s.nodata);
  const std::size_t bytes = s.bits / 8;
  std::vector<std::uint8_t> image(static_cast<std::size_t>(kW) * kH * bytes);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const bool hole = x >= 10 && x <= 12 && y >= 5 && y <= 7;
      const double v = hole ? s.hole : truth(x, y);
      std::uint8_t* p = image.data() + (static_cast<std::size_t>(y) * kW + x) * bytes;
      if (s.sampleFormat == SAMPLEFORMAT_IEEEFP) {
        const auto f = static_cast<float>(v);
        std::memcpy(p, &f, 4);
      } else if (s.sampleFormat == SAMPLEFORMAT_INT) {
        const auto i = static_cast<std::int16_t>(v);
        std::memcpy(p, &i, 2);
      } else {
        const auto u = static_cast<std::uint16_t>(hole ? 0 : v);
        std::memcpy(p, &u, 2);
      }
    }
  }
  if (s.tiled) {
    TIFFSetField(tif, TIFFTAG_TILEWIDTH, 16);
    TIFFSetField(tif, TIFFTAG_TILELENGTH, 16);
    std::vector<std::uint8_t> tile(16 * 16 * bytes);
    for (int ty = 0; ty < kH; ty += 16) {
      for (int tx = 0; tx < kW; tx += 16) {
        std::fill(tile.begin(), tile.end(), 0);
        for (int y = 0; y < 16 && ty + y < kH; ++y) {
          for (int x = 0; x < 16 && tx + x < kW; ++x) {
            std::memcpy(tile.data() + (y * 16 + x) * bytes,
                        image.data() + (static_cast<std::size_t>(ty + y) * kW + tx + x) * bytes, bytes);
          }
        }
        ASSERT_GE(TIFFWriteTile(tif, tile.data(), static_cast<std::uint32_t>(tx), static_cast<std::uint32_t>(ty), 0, 0),
                  0);
      }
    }
  } else {
    TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, 4);
    for (int y = 0; y < kH; ++y) {
      ASSERT_EQ(TIFFWriteScanline(tif, image.data() + static_cast<std::size_t>(y) * kW * bytes,
                                  static_cast<std::uint32_t>(y), 0),
                1);
    }
  }
  TIFFClose(tif);
}

void expectHoleFilled(const ElevationGrid& g) {
  EXPECT_EQ(g.nodataFilled, 9u);
  // Filled from the surroundings: within the range of the ring of samples around the hole.
  double ringMin = 1e9, ringMax = -1e9;
  for (int y = 4; y <= 8; ++y) {
    for (int x = 9; x <= 13; ++x) {
      if (x == 9 || x == 13 || y == 4 || y == 8) {
        ringMin = std::min(ringMin, truth(x, y));
        ringMax = std::max(ringMax, truth(x, y));
      }
    }
  }
  for (int j = 0; j < kH; ++j) {
    for (int i = 0; i < kW; ++i) {
      const int y = kH - 1 - j;
      const bool hole = i >= 10 && i <= 12 && y >= 5 && y <= 7;
      const double v = g.heightsM[static_cast<std::size_t>(j) * kW + i];
      if (hole) {
        EXPECT_GE(v, ringMin - 1e-3);
        EXPECT_LE(v, ringMax + 1e-3);
      } else {
        ASSERT_NEAR(v, truth(i, y), 1e-4);
      }
    }
  }
}

TEST(GeoTiffImport, TagsGiveSpacingOriginAndNodata) {
  ScratchDir dir;
  writeGeoTiff(dir / "geo.tif", {});
  const ElevationGrid g = importElevation(dir / "geo.tif");
  EXPECT_TRUE(g.spacingFromFile);
  EXPECT_EQ(g.spacingM, 10.0);
  // Centre of the south-west pixel: half a pixel in from the left edge and the bottom edge.
  EXPECT_DOUBLE_EQ(g.originM.x, 500005.0);
  EXPECT_DOUBLE_EQ(g.originM.y, 4100000.0 - (kH - 0.5) * 10.0);
  expectHoleFilled(g);
}

// GDAL_NODATA "-9999.9" over Float32 samples: the samples hold the float nearest it, which is not
// the double -9999.9; compared in double the hole stayed a 10 km pit.
TEST(GeoTiffImport, AFractionalNodataMatchesItsFloatSamples) {
  ScratchDir dir;
  GeoTiffSpec spec;
  spec.nodata = "-9999.9";
  spec.hole = -9999.9;
  writeGeoTiff(dir / "geo.tif", spec);
  expectHoleFilled(importElevation(dir / "geo.tif"));
}

TEST(GeoTiffImport, PixelIsPointTiesThePixelCentre) {
  ScratchDir dir;
  GeoTiffSpec spec;
  spec.pixelIsPoint = true;
  writeGeoTiff(dir / "geo.tif", spec);
  const ElevationGrid g = importElevation(dir / "geo.tif");
  EXPECT_DOUBLE_EQ(g.originM.x, 500000.0);
  EXPECT_DOUBLE_EQ(g.originM.y, 4100000.0 - (kH - 1) * 10.0);
}

TEST(GeoTiffImport, Int16StripedLzw) {
  ScratchDir dir;
  GeoTiffSpec spec;
  spec.sampleFormat = SAMPLEFORMAT_INT;
  spec.bits = 16;
  spec.compression = COMPRESSION_LZW;
  spec.tiled = false;
  writeGeoTiff(dir / "geo.tif", spec);
  expectHoleFilled(importElevation(dir / "geo.tif"));
}

TEST(GeoTiffImport, Uint16TiledUncompressedWithNodataFromTheOptions) {
  ScratchDir dir;
  GeoTiffSpec spec;
  spec.sampleFormat = SAMPLEFORMAT_UINT;
  spec.bits = 16;
  spec.compression = COMPRESSION_NONE;
  spec.nodata = nullptr;
  writeGeoTiff(dir / "geo.tif", spec);
  ImportOptions options;
  options.nodata = 0.0;
  expectHoleFilled(importElevation(dir / "geo.tif", options));
}

// A GeoTIFF whose pixel scale is stored as two SHORTs, not DOUBLEs: refused, naming the tag. It was
// read as doubles, 16 bytes from a 4-byte buffer (a heap overflow; ASan's stage shows it).
TEST(GeoTiffImport, ATagOfTheWrongTypeIsRefused) {
  ScratchDir dir;
  const std::filesystem::path path = dir / "short_scale.tif";
  TIFF* tif = TIFFOpen(path.c_str(), "w");
  ASSERT_NE(tif, nullptr);
  static const TIFFFieldInfo kShortScale[] = {
      {33550, -1, -1, TIFF_SHORT, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelPixelScaleTag")}};
  TIFFMergeFieldInfo(tif, kShortScale, 1);
  TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, 4);
  TIFFSetField(tif, TIFFTAG_IMAGELENGTH, 4);
  TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 16);
  TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_UINT);
  TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, 4);
  const std::uint16_t scale[2] = {10, 10};
  TIFFSetField(tif, 33550, 2, scale);
  std::uint16_t row[4] = {100, 200, 300, 400};
  for (std::uint32_t y = 0; y < 4; ++y) ASSERT_EQ(TIFFWriteScanline(tif, row, y, 0), 1);
  TIFFClose(tif);
  expectImportError([&] { importElevation(path); }, {"short_scale.tif", "GeoTIFF tag 33550", "not 12"});
}

// ---------------------------------------------------------------------------------------------
// 16-bit PNG, and images that are not elevation.

TEST(PngImport, SixteenBitGreyWithAVerticalScale) {
  ScratchDir dir;
  const std::filesystem::path path = dir / "dem.png";
  OIIO::ImageSpec spec(kW, kH, 1, OIIO::TypeDesc::UINT16);
  std::vector<std::uint16_t> counts;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) counts.push_back(static_cast<std::uint16_t>((truth(x, y) + 100.0) * 10.0));
  }
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out->open(path.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT16, counts.data()));
  ASSERT_TRUE(out->close());
  ImportOptions options;
  options.verticalScaleM = 0.1;
  options.verticalOffsetM = -100.0;
  options.spacingM = 2.0;
  expectMatchesTruth(importElevation(path, options), 1e-3);
}

TEST(PngImport, AColourPhotoIsNotElevation) {
  ScratchDir dir;
  const std::filesystem::path path = dir / "photo.png";
  OIIO::ImageSpec spec(8, 8, 3, OIIO::TypeDesc::UINT8);
  const std::vector<std::uint8_t> pixels(8 * 8 * 3, 128);
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out->open(path.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
  ASSERT_TRUE(out->close());
  expectImportError([&] { importElevation(path); }, {"photo.png", "not elevation data: 3 channels"});
}

TEST(PngImport, GarbageIsRejectedWithTheFileName) {
  ScratchDir dir;
  testing::writeFile(dir / "junk.png", std::vector<char>(100, 'x'));
  expectImportError([&] { importElevation(dir / "junk.png"); }, {"junk.png", "cannot read"});
  expectImportError([&] { importElevation(dir / "absent.tif"); }, {"absent.tif", "no such file"});
}

// ---------------------------------------------------------------------------------------------
// ESRI ASCII grid.

std::string asciiGrid(bool withHole) {
  std::string text = "ncols " + std::to_string(kW) + "\nnrows " + std::to_string(kH) +
                     "\nxllcorner 1000\nyllcorner 2000.5\ncellsize 25\nNODATA_value -9999\n";
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const bool hole = withHole && x >= 10 && x <= 12 && y >= 5 && y <= 7;
      text += hole ? "-9999" : std::to_string(truth(x, y));
      text += x + 1 < kW ? " " : "\n";
    }
  }
  return text;
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

TEST(AsciiGridImport, ReadsHeaderValuesAndNodata) {
  ScratchDir dir;
  writeText(dir / "dem.asc", asciiGrid(true));
  const ElevationGrid g = importElevation(dir / "dem.asc");
  EXPECT_EQ(g.spacingM, 25.0);
  EXPECT_DOUBLE_EQ(g.originM.x, 1012.5);
  EXPECT_DOUBLE_EQ(g.originM.y, 2013.0);
  expectHoleFilled(g);
}

TEST(AsciiGridImport, ErrorsNameTheFileLineAndProblem) {
  ScratchDir dir;
  std::string bad = asciiGrid(false);
  bad.replace(bad.find("cellsize"), 8, "cellsise");
  writeText(dir / "a.asc", bad);
  expectImportError([&] { importElevation(dir / "a.asc"); }, {"a.asc:5:", "unknown header key 'cellsise'"});

  std::string word = asciiGrid(false);
  word.replace(word.find('\n', word.find("NODATA")) + 1, 3, "1x3");
  writeText(dir / "b.asc", word);
  expectImportError([&] { importElevation(dir / "b.asc"); }, {"b.asc:7:", "expected a number, got '1x3"});

  std::string truncated = asciiGrid(false);
  truncated.resize(truncated.size() - 40);
  writeText(dir / "c.asc", truncated);
  expectImportError([&] { importElevation(dir / "c.asc"); }, {"c.asc", "truncated"});

  writeText(dir / "d.asc", "nrows 3\ncellsize 1\n1 2 3\n");
  expectImportError([&] { importElevation(dir / "d.asc"); }, {"d.asc", "no 'ncols'"});

  writeText(dir / "e.asc", "ncols 100000000\nnrows 100000000\ncellsize 1\n1\n");
  expectImportError([&] { importElevation(dir / "e.asc"); }, {"e.asc", "out of range"});

  // A header within the limits but asking for far more values than the file holds (262144² would
  // be 550 GB of heights): refused before anything is sized, as a clear error, not bad_alloc
  writeText(dir / "f.asc", "ncols 262144\nnrows 262144\ncellsize 1\n1 2 3\n");
  expectImportError([&] { importElevation(dir / "f.asc"); }, {"f.asc", "68719476736 values", "truncated"});
}

// ---------------------------------------------------------------------------------------------
// Raw grids with a sidecar.

TEST(RawGridImport, Int16NorthFirstWithSidecar) {
  ScratchDir dir;
  const std::vector<std::int16_t> samples = truthPixels<std::int16_t>();
  std::vector<char> bytes(samples.size() * 2);
  std::memcpy(bytes.data(), samples.data(), bytes.size());
  testing::writeFile(dir / "dem.raw", bytes);
  writeText(dir / "dem.raw.toml", "width = " + std::to_string(kW) + "\nheight = " + std::to_string(kH) +
                                      "\ntype = \"int16\"\nspacing_m = 4.0\norigin_x_m = 10.0\norigin_y_m = 20.0\n");
  const ElevationGrid g = importElevation(dir / "dem.raw");
  expectMatchesTruth(g);
  EXPECT_EQ(g.spacingM, 4.0);
  EXPECT_EQ(g.originM, glm::dvec2(10.0, 20.0));
}

// Nodata -1 and, in the samples' own precision, -9999.9 (the float nearest it is not the double)
TEST(RawGridImport, Float32SouthFirstWithNodata) {
  for (const double nodata : {-1.0, -9999.9}) {
    ScratchDir dir;
    std::vector<float> samples;
    for (int j = 0; j < kH; ++j) {  // south row first
      for (int i = 0; i < kW; ++i) {
        const int y = kH - 1 - j;
        const bool hole = i >= 10 && i <= 12 && y >= 5 && y <= 7;
        samples.push_back(hole ? static_cast<float>(nodata) : static_cast<float>(truth(i, y)));
      }
    }
    std::vector<char> bytes(samples.size() * 4);
    std::memcpy(bytes.data(), samples.data(), bytes.size());
    testing::writeFile(dir / "dem.f32", bytes);
    char sidecar[160];
    std::snprintf(sidecar, sizeof sidecar,
                  "width = %d\nheight = %d\ntype = \"float32\"\nrow_order = \"south_first\"\nnodata = %.1f\n", kW, kH,
                  nodata);
    writeText(dir / "dem.toml", sidecar);
    expectHoleFilled(importElevation(dir / "dem.f32"));
  }
}

TEST(RawGridImport, SizeMismatchAndMissingSidecarAreClearErrors) {
  ScratchDir dir;
  testing::writeFile(dir / "dem.raw", std::vector<char>(100, 0));
  expectImportError([&] { importElevation(dir / "dem.raw"); }, {"dem.raw", "without a sidecar"});
  writeText(dir / "dem.raw.toml", "width = 10\nheight = 10\ntype = \"int16\"\n");
  expectImportError([&] { importElevation(dir / "dem.raw"); }, {"dem.raw", "expected 200 bytes", "has 100"});
  writeText(dir / "dem.raw.toml", "width = 10\nheight = 10\ntype = \"int64\"\n");
  expectImportError([&] { importElevation(dir / "dem.raw"); }, {"dem.raw.toml", "type: expected"});
  // A misspelt key is an error, not a silently default spacing.
  writeText(dir / "dem.raw.toml", "width = 10\nheight = 10\nspaceing_m = 2\n");
  expectImportError([&] { importElevation(dir / "dem.raw"); }, {"dem.raw.toml:3: spaceing_m: unknown key"});
  ImportOptions options;
  options.rawWidth = 10;
  options.rawHeight = 5;
  std::filesystem::remove(dir / "dem.raw.toml");
  EXPECT_EQ(importElevation(dir / "dem.raw", options).heightVox, 5);
}

// ---------------------------------------------------------------------------------------------
// Hole filling, quantisation, orthophoto.

TEST(FillNodata, AWideHoleInAPlaneIsFilledSmoothly) {
  const int w = 64, h = 48;
  std::vector<float> z(static_cast<std::size_t>(w) * h);
  std::vector<std::uint8_t> valid(z.size(), 1);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * w + i;
      z[k] = static_cast<float>(i + 2 * j);
      if (i > 10 && i < 50 && j > 8 && j < 40) {
        valid[k] = 0;
        z[k] = -1e9f;  // garbage that must not leak into the fill
      }
    }
  }
  EXPECT_EQ(fillNodata(z, valid, w, h), 39u * 31u);
  for (int j = 9; j < 40; ++j) {
    for (int i = 11; i < 50; ++i) {
      const float v = z[static_cast<std::size_t>(j) * w + i];
      ASSERT_GT(v, 10.0f);
      ASSERT_LT(v, 50.0f + 80.0f);
    }
  }
  std::vector<std::uint8_t> none(z.size(), 0);
  EXPECT_THROW(fillNodata(z, none, w, h), ImportError);
}

TEST(ElevationImport, QuantisedHeightsStayWithinHalfAStep) {
  ScratchDir dir;
  writeText(dir / "dem.asc", asciiGrid(false));
  const ElevationGrid g = importElevation(dir / "dem.asc");
  const TerrainGrid q = quantiseElevation(g);
  for (std::size_t k = 0; k < g.heightsM.size(); ++k) {
    ASSERT_NEAR(q.geometry.heightM(q.heightQ[k]), g.heightsM[k], 0.5 * q.geometry.heightStepM + 1e-6);
  }
  EXPECT_EQ(q.geometry.spacingM, 25.0);
}

TEST(Orthophoto, StretchedOverTheGridNorthUp) {
  ScratchDir dir;
  const std::filesystem::path path = dir / "ortho.png";
  // 2×2 photo: top row red, green; bottom row blue, white.
  const std::uint8_t pixels[] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out->open(path.string(), OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels));
  ASSERT_TRUE(out->close());
  TerrainGeometry g;
  g.widthVox = 8;
  g.heightVox = 8;
  const std::vector<std::uint32_t> c = drapeOrthophoto(path, g, {}, ColourOutput::Colour);
  EXPECT_EQ(c[7 * 8 + 0], packRgba(255, 0, 0));      // north-west voxel: red
  EXPECT_EQ(c[7 * 8 + 7], packRgba(0, 255, 0));      // north-east: green
  EXPECT_EQ(c[0 * 8 + 0], packRgba(0, 0, 255));      // south-west: blue
  EXPECT_EQ(c[0 * 8 + 7], packRgba(255, 255, 255));  // south-east: white
  const std::vector<std::uint32_t> grey = drapeOrthophoto(path, g, {}, ColourOutput::Grey);
  EXPECT_EQ(grey[7 * 8 + 0], packRgba(77, 77, 77));
  EXPECT_THROW(drapeOrthophoto(dir / "none.png", g, {}, ColourOutput::Colour), std::runtime_error);
}

}  // namespace
}  // namespace fieldcast::core
