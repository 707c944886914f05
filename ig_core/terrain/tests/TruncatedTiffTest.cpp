// A striped, compressed TIFF cut short (an interrupted download or copy) must be refused, not
// imported with the missing strips as terrain at 0 m. The files are laid out the way GDAL writes
// them — directory first, strips after — so cutting the tail loses strips but keeps the directory
// (libtiff alone writes the directory last, and a cut there is refused anyway). The strips are
// compressed by libtiff; the file around them is assembled here.
#include <ig_core/ElevationImport.h>

#include "TerrainTestUtil.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tiffio.h>

#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>
#include <vector>

namespace fieldcast::core {
namespace {

using ::testing::HasSubstr;
using testing::ScratchDir;

constexpr int kSide = 64;
constexpr int kRowsPerStrip = 8;

std::int16_t heightAt(int x, int y) { return static_cast<std::int16_t>(500 + 3 * x + 5 * y + (x * y) % 13); }

// Compresses kSide² int16 heights into strips with libtiff; returns each strip's raw bytes.
std::vector<std::vector<char>> compressedStrips(const std::filesystem::path& scratch, std::uint16_t compression) {
  TIFF* tif = TIFFOpen(scratch.c_str(), "w");
  EXPECT_NE(tif, nullptr);
  TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, kSide);
  TIFFSetField(tif, TIFFTAG_IMAGELENGTH, kSide);
  TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 16);
  TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_INT);
  TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tif, TIFFTAG_COMPRESSION, compression);
  TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, kRowsPerStrip);
  std::vector<std::int16_t> row(kSide);
  for (int y = 0; y < kSide; ++y) {
    for (int x = 0; x < kSide; ++x) row[static_cast<std::size_t>(x)] = heightAt(x, y);
    EXPECT_EQ(TIFFWriteScanline(tif, row.data(), static_cast<std::uint32_t>(y), 0), 1);
  }
  TIFFClose(tif);
  tif = TIFFOpen(scratch.c_str(), "r");
  std::vector<std::vector<char>> strips;
  for (std::uint32_t s = 0; s < TIFFNumberOfStrips(tif); ++s) {
    std::vector<char> bytes(static_cast<std::size_t>(TIFFGetStrileByteCount(tif, s)));
    EXPECT_EQ(TIFFReadRawStrip(tif, s, bytes.data(), static_cast<tmsize_t>(bytes.size())),
              static_cast<tmsize_t>(bytes.size()));
    strips.push_back(std::move(bytes));
  }
  TIFFClose(tif);
  return strips;
}

template <typename T>
void put(std::vector<char>& out, T value) {
  const auto* p = reinterpret_cast<const char*>(&value);
  out.insert(out.end(), p, p + sizeof(T));
}

// A little-endian TIFF: header, directory, strip offset and byte count arrays, then the strips.
std::vector<char> directoryFirstTiff(const std::vector<std::vector<char>>& strips, std::uint16_t compression) {
  constexpr std::uint16_t kShort = 3, kLong = 4;
  constexpr std::uint16_t kEntries = 11;
  const auto stripCount = static_cast<std::uint32_t>(strips.size());
  const std::uint32_t offsetsAt = 8 + 2 + 12 * kEntries + 4;
  const std::uint32_t countsAt = offsetsAt + 4 * stripCount;
  std::uint32_t dataAt = countsAt + 4 * stripCount;
  std::vector<char> out{'I', 'I', 42, 0};
  put<std::uint32_t>(out, 8);
  put<std::uint16_t>(out, kEntries);
  const auto entry = [&](std::uint16_t tag, std::uint16_t type, std::uint32_t count, std::uint32_t value) {
    put(out, tag);
    put(out, type);
    put(out, count);
    if (type == kShort && count == 1) {
      put<std::uint16_t>(out, static_cast<std::uint16_t>(value));
      put<std::uint16_t>(out, 0);
    } else {
      put(out, value);
    }
  };
  entry(TIFFTAG_IMAGEWIDTH, kLong, 1, kSide);
  entry(TIFFTAG_IMAGELENGTH, kLong, 1, kSide);
  entry(TIFFTAG_BITSPERSAMPLE, kShort, 1, 16);
  entry(TIFFTAG_COMPRESSION, kShort, 1, compression);
  entry(TIFFTAG_PHOTOMETRIC, kShort, 1, PHOTOMETRIC_MINISBLACK);
  entry(TIFFTAG_STRIPOFFSETS, kLong, stripCount, offsetsAt);
  entry(TIFFTAG_SAMPLESPERPIXEL, kShort, 1, 1);
  entry(TIFFTAG_ROWSPERSTRIP, kLong, 1, kRowsPerStrip);
  entry(TIFFTAG_STRIPBYTECOUNTS, kLong, stripCount, countsAt);
  entry(TIFFTAG_PLANARCONFIG, kShort, 1, PLANARCONFIG_CONTIG);
  entry(TIFFTAG_SAMPLEFORMAT, kShort, 1, SAMPLEFORMAT_INT);
  put<std::uint32_t>(out, 0);  // no next directory
  for (const std::vector<char>& s : strips) {
    put(out, dataAt);
    dataAt += static_cast<std::uint32_t>(s.size());
  }
  for (const std::vector<char>& s : strips) put(out, static_cast<std::uint32_t>(s.size()));
  for (const std::vector<char>& s : strips) out.insert(out.end(), s.begin(), s.end());
  return out;
}

struct Compression {
  const char* name;
  std::uint16_t code;
};
void PrintTo(const Compression& c, std::ostream* os) { *os << c.name; }

class TruncatedTiff : public ::testing::TestWithParam<Compression> {
 protected:
  // Writes the whole directory-first file and returns it.
  std::vector<char> writeWhole(const ScratchDir& dir) {
    const std::vector<std::vector<char>> strips = compressedStrips(dir / "libtiff.tif", GetParam().code);
    EXPECT_EQ(strips.size(), static_cast<std::size_t>(kSide / kRowsPerStrip));
    const std::vector<char> whole = directoryFirstTiff(strips, GetParam().code);
    testing::writeFile(dir / "whole.tif", whole);
    return whole;
  }
};

TEST_P(TruncatedTiff, TheWholeFileImportsEveryHeight) {
  ScratchDir dir;
  writeWhole(dir);
  ImportOptions options;
  options.spacingM = 5.0;
  const ElevationGrid g = importElevation(dir / "whole.tif", options);
  ASSERT_EQ(g.widthVox, kSide);
  ASSERT_EQ(g.heightVox, kSide);
  for (int j = 0; j < kSide; ++j) {
    for (int i = 0; i < kSide; ++i) {
      ASSERT_EQ(g.heightsM[static_cast<std::size_t>(j) * kSide + i], heightAt(i, kSide - 1 - j)) << i << ", " << j;
    }
  }
}

TEST_P(TruncatedTiff, AFileCutShortIsAnImportErrorNamingIt) {
  ScratchDir dir;
  std::vector<char> bytes = writeWhole(dir);
  bytes.resize(bytes.size() * 3 / 5);  // the last three of eight strips are lost, one in part
  testing::writeFile(dir / "cut.tif", bytes);
  ImportOptions options;
  options.spacingM = 5.0;
  try {
    const ElevationGrid g = importElevation(dir / "cut.tif", options);
    FAIL() << "a cut file imported (lowest height " << g.minM << " m)";
  } catch (const ImportError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cut.tif"));
    EXPECT_THAT(e.what(), HasSubstr("cut short"));
  }
}

TEST_P(TruncatedTiff, AStripThatDoesNotDecodeIsAnImportError) {
  ScratchDir dir;
  std::vector<char> bytes = writeWhole(dir);
  // Overwrite most of the data with garbage that neither LZW nor Deflate decodes cleanly; the
  // file keeps its length, so only the decoder can tell.
  const std::size_t dataStart = bytes.size() / 4;
  for (std::size_t k = dataStart; k < bytes.size(); ++k) bytes[k] = static_cast<char>(0xFF);
  testing::writeFile(dir / "garbled.tif", bytes);
  ImportOptions options;
  options.spacingM = 5.0;
  try {
    const ElevationGrid g = importElevation(dir / "garbled.tif", options);
    FAIL() << "a garbled file imported (lowest height " << g.minM << " m)";
  } catch (const ImportError& e) {
    EXPECT_THAT(e.what(), HasSubstr("garbled.tif"));
  }
}

INSTANTIATE_TEST_SUITE_P(StripedCompressed, TruncatedTiff,
                         ::testing::Values(Compression{"Lzw", COMPRESSION_LZW},
                                           Compression{"Deflate", COMPRESSION_ADOBE_DEFLATE}),
                         [](const ::testing::TestParamInfo<Compression>& param) { return param.param.name; });

}  // namespace
}  // namespace fieldcast::core
