#pragma once
// The per-format elevation readers behind importElevation(). Each returns heights (row 0 = south)
// with validity flags; the caller fills holes and applies the options.

#include <ig_core/ElevationImport.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace fieldcast::core::detail {

/// A grid as read, before hole filling.
struct RawElevation {
  int width = 0;
  int height = 0;
  std::vector<float> heightsM;        // row 0 = south
  std::vector<std::uint8_t> valid;    // 1: a real sample
  std::optional<double> spacingM;     // from the file
  std::optional<glm::dvec2> originM;  // centre of the south-west voxel, from the file
};

/// GeoTIFF georeferencing of a TIFF, when it has any.
struct GeoTiffInfo {
  std::optional<double> pixelSizeX;  // ModelPixelScale / ModelTransformation, in CRS units
  std::optional<double> pixelSizeY;
  std::optional<double> tieX;  // CRS position of the top-left corner of pixel (0, 0)
  std::optional<double> tieY;
  std::optional<double> nodata;  // GDAL_NODATA
  bool geographic = false;       // CRS in degrees (GTModelTypeGeoKey = 2)
};

/// Reads the GeoTIFF tags of `path` with libtiff. Throws ImportError on a rotated/sheared transform.
GeoTiffInfo readGeoTiffTags(const std::filesystem::path& path);

/// Any single-channel image OpenImageIO reads (TIFF, PNG, …).
RawElevation readElevationImage(const std::filesystem::path& path, const ImportOptions& options);
/// ESRI ASCII grid.
RawElevation readAsciiGrid(const std::filesystem::path& path, const ImportOptions& options);
/// Raw little-endian samples with a TOML sidecar (or sizes from the options).
RawElevation readRawGrid(const std::filesystem::path& path, const ImportOptions& options);

}  // namespace fieldcast::core::detail
