// GeoTIFF georeferencing tags through libtiff (OpenImageIO 2.4 does not expose them).
// Tags: ModelPixelScale 33550, ModelTiepoint 33922, ModelTransformation 34264,
// GeoKeyDirectory 34735 (GTModelType 1024, GTRasterType 1025, GeographicType 2048,
// ProjectedCSType 3072), GDAL_NODATA 42113.
#include "ElevationReaders.h"

#include <tiffio.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>

namespace fieldcast::core::detail {
namespace {

constexpr ttag_t kModelPixelScale = 33550;
constexpr ttag_t kModelTiepoint = 33922;
constexpr ttag_t kModelTransformation = 34264;
constexpr ttag_t kGeoKeyDirectory = 34735;
constexpr ttag_t kGdalNodata = 42113;

// libtiff reports unknown (private) tags as warnings; they are exactly the tags read here.
void quiet(const char*, const char*, va_list) {}

// The tags' types in the GeoTIFF specification: the scale, tie points and transformation DOUBLE,
// the key directory SHORT; GDAL's nodata ASCII.
template <typename T>
constexpr TIFFDataType kTagType = std::is_same_v<T, double>          ? TIFF_DOUBLE
                                  : std::is_same_v<T, std::uint16_t> ? TIFF_SHORT
                                                                     : TIFF_ASCII;

template <typename T>
bool getArray(TIFF* tif, const std::filesystem::path& path, ttag_t tag, std::uint32_t& count, const T*& data) {
  static_assert(std::is_same_v<T, double> || std::is_same_v<T, std::uint16_t> || std::is_same_v<T, char>);
  void* raw = nullptr;
  count = 0;
  const TIFFField* field = TIFFFindField(tif, tag, TIFF_ANY);
  if (field == nullptr) return false;
  // libtiff does not know these tags: it keeps them in whatever type the file declares, and a
  // SHORT pixel scale read as doubles runs past its buffer
  if (TIFFFieldDataType(field) != kTagType<T>) {
    throw ImportError(path.string() + ": GeoTIFF tag " + std::to_string(tag) + " is stored as TIFF type " +
                      std::to_string(static_cast<int>(TIFFFieldDataType(field))) + ", not " +
                      std::to_string(static_cast<int>(kTagType<T>)));
  }
  if (TIFFFieldPassCount(field) != 0) {
    if (TIFFFieldReadCount(field) == TIFF_VARIABLE2) {
      if (TIFFGetField(tif, tag, &count, &raw) != 1) return false;
    } else {
      std::uint16_t shortCount = 0;
      if (TIFFGetField(tif, tag, &shortCount, &raw) != 1) return false;
      count = shortCount;
    }
  } else {
    if (TIFFGetField(tif, tag, &raw) != 1) return false;
    count = static_cast<std::uint32_t>(TIFFFieldReadCount(field));
  }
  data = static_cast<const T*>(raw);
  return data != nullptr;
}

}  // namespace

GeoTiffInfo readGeoTiffTags(const std::filesystem::path& path) {
  GeoTiffInfo info;
  const TIFFErrorHandler oldWarning = TIFFSetWarningHandler(quiet);
  std::unique_ptr<TIFF, decltype(&TIFFClose)> tif(TIFFOpen(path.c_str(), "r"), &TIFFClose);
  TIFFSetWarningHandler(oldWarning);
  if (!tif) return info;  // OpenImageIO reports unreadable files with its own message

  std::uint32_t count = 0;
  const double* values = nullptr;
  if (getArray(tif.get(), path, kModelPixelScale, count, values) && count >= 2) {
    info.pixelSizeX = values[0];
    info.pixelSizeY = values[1];
  }
  if (getArray(tif.get(), path, kModelTiepoint, count, values) && count >= 6) {
    // (i, j, k) in raster space maps to (x, y, z); bring it to the corner of pixel (0, 0).
    if (info.pixelSizeX && info.pixelSizeY) {
      info.tieX = values[3] - values[0] * *info.pixelSizeX;
      info.tieY = values[4] + values[1] * *info.pixelSizeY;
    }
  }
  if (getArray(tif.get(), path, kModelTransformation, count, values) && count >= 16) {
    if (std::fabs(values[1]) > 1e-12 || std::fabs(values[4]) > 1e-12) {
      throw ImportError(path.string() +
                        ": GeoTIFF ModelTransformation is rotated or sheared; resample it to a "
                        "north-up grid first (e.g. gdalwarp)");
    }
    info.pixelSizeX = values[0];
    info.pixelSizeY = -values[5];
    info.tieX = values[3];
    info.tieY = values[7];
  }
  const std::uint16_t* keys = nullptr;
  bool pixelIsPoint = false;
  std::uint16_t geographicCode = 0, projectedCode = 0;
  if (getArray(tif.get(), path, kGeoKeyDirectory, count, keys) && count >= 4) {
    const std::uint32_t keyCount = keys[3];
    for (std::uint32_t k = 0; k < keyCount && 4 + 4 * k + 3 < count; ++k) {
      const std::uint16_t* key = keys + 4 + 4 * k;
      if (key[1] != 0) continue;  // value stored elsewhere: not one of the short keys used here
      if (key[0] == 1024) info.geographic = key[3] == 2;
      if (key[0] == 1025) pixelIsPoint = key[3] == 2;
      if (key[0] == 2048) geographicCode = key[3];
      if (key[0] == 3072) projectedCode = key[3];
    }
  }
  constexpr std::uint16_t kUserDefined = 32767;
  const std::uint16_t code = info.geographic ? geographicCode : projectedCode;
  if (code != 0 && code != kUserDefined) info.epsg = code;
  // PixelIsPoint: the tie point is the centre of pixel (0, 0), not its corner.
  if (pixelIsPoint && info.tieX && info.pixelSizeX && info.pixelSizeY) {
    *info.tieX -= 0.5 * *info.pixelSizeX;
    *info.tieY += 0.5 * *info.pixelSizeY;
  }
  const char* text = nullptr;
  std::uint32_t textCount = 0;
  if (getArray(tif.get(), path, kGdalNodata, textCount, text) && textCount > 0) {
    const std::string s(text, strnlen(text, textCount));
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end != s.c_str()) info.nodata = v;
  }
  return info;
}

}  // namespace fieldcast::core::detail
