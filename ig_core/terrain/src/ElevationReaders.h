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
  std::string crs;                    // CRS of originM ("EPSG:n" or WKT); empty when the file has none
};

/// GeoTIFF georeferencing of a TIFF, when it has any.
struct GeoTiffInfo {
  std::optional<double> pixelSizeX;  // ModelPixelScale / ModelTransformation, in CRS units
  std::optional<double> pixelSizeY;
  std::optional<double> tieX;  // CRS position of the top-left corner of pixel (0, 0)
  std::optional<double> tieY;
  std::optional<double> nodata;  // GDAL_NODATA
  bool geographic = false;       // CRS in degrees (GTModelTypeGeoKey = 2)
  /// EPSG code of the CRS: ProjectedCSTypeGeoKey (3072) for a projected grid, GeographicTypeGeoKey
  /// (2048) for a geographic one; empty when absent or user-defined (32767).
  std::optional<int> epsg;
};

/// A grid in geographic degrees, as its GeoTIFF places it.
struct GeographicPlacement {
  double westDeg = 0.0;   // longitude of the west edge of pixel (0, 0)
  double northDeg = 0.0;  // latitude of its north edge
  double stepXDeg = 0.0;  // pixel size
  double stepYDeg = 0.0;
  std::string crs;  // the geographic CRS ("EPSG:4326", …)
};

/// Reprojects a grid in degrees (rows running north) onto a square metric grid in a transverse
/// Mercator projection centred on it (PROJ), sampled bilinearly; voxels outside the source stay
/// invalid (filled later like nodata). Sets spacing, origin and the CRS (as WKT). Throws ImportError.
RawElevation reprojectGeographic(const RawElevation& degrees, const GeographicPlacement& placement,
                                 const std::filesystem::path& path);

/// Reads the GeoTIFF tags of `path` with libtiff. Throws ImportError on a rotated/sheared transform.
GeoTiffInfo readGeoTiffTags(const std::filesystem::path& path);

/// Throws ImportError when a strip or tile of the TIFF at `path` lies past the end of the file.
void checkTiffComplete(const std::filesystem::path& path);

/// Any single-channel image OpenImageIO reads (TIFF, PNG, …).
RawElevation readElevationImage(const std::filesystem::path& path, const ImportOptions& options);
/// ESRI ASCII grid.
RawElevation readAsciiGrid(const std::filesystem::path& path, const ImportOptions& options);
/// Raw little-endian samples with a TOML sidecar (or sizes from the options).
RawElevation readRawGrid(const std::filesystem::path& path, const ImportOptions& options);

}  // namespace fieldcast::core::detail
