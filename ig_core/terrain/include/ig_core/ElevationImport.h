#pragma once
// Import of real elevation data: GeoTIFF/TIFF (int16, uint16, float32, …; striped or tiled;
// uncompressed, LZW or Deflate) and 16-bit PNG through OpenImageIO, with the GeoTIFF tags
// (ModelPixelScale, ModelTiepoint, ModelTransformation, GDAL_NODATA, raster type) read through
// libtiff; ESRI ASCII grids (.asc); raw little-endian grids with a small TOML sidecar.
// GeoTIFF CRSs given by EPSG code are kept; grids in geographic degrees are reprojected (PROJ)
// onto a square metric grid in a transverse Mercator projection centred on the grid.
// Nodata holes are filled (push-pull interpolation) and counted.

#include <ig_core/TerrainBuilder.h>

#include <glm/vec2.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace fieldcast::core {

/// Input that cannot be imported; what() names the file (and line) and what was expected.
class ImportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Elevation in metres on a regular grid, rows running north (row 0 is the southern edge).
struct ElevationGrid {
  int widthVox = 0;
  int heightVox = 0;
  double spacingM = 1.0;         ///< voxel pitch (square voxels)
  glm::dvec2 originM{0.0, 0.0};  ///< world x, y of the centre of the south-west voxel
  /// CRS of world x, y ("EPSG:n" or WKT, DatabaseLayout::crs); empty when the file has none.
  /// Geographic (degree) grids come reprojected to a transverse Mercator centred on the grid.
  std::string crs;
  std::vector<float> heightsM;  ///< W×H, holes filled
  double minM = 0.0;
  double maxM = 0.0;
  std::size_t nodataFilled = 0;  ///< voxels that were nodata and got interpolated
  bool spacingFromFile = false;  ///< false: options.spacingM or the 1 m default was used
};

/// What the file cannot say for itself.
struct ImportOptions {
  double spacingM = 0.0;         ///< > 0: overrides the file; used when the file has none (default 1 m)
  std::optional<double> nodata;  ///< nodata value when the file declares none
  double verticalScaleM = 1.0;   ///< metres per count for integer images without units (16-bit PNG)
  double verticalOffsetM = 0.0;  ///< metres at count 0
  int rawWidth = 0;              ///< raw grids without a sidecar: size and sample type
  int rawHeight = 0;
  std::string rawType = "int16";  ///< "int16", "uint16" or "float32"
};

/// Reads `path`, choosing the reader by extension: .tif/.tiff, .png (and other images OpenImageIO
/// reads), .asc, .raw/.bin/.r16/.r32. Throws ImportError naming the file and what was wrong.
ElevationGrid importElevation(const std::filesystem::path& path, const ImportOptions& options = {});

/// Fills the voxels whose `valid` flag is 0 by push-pull interpolation (smooth across holes of any
/// size) and returns how many were filled. Throws ImportError when nothing is valid.
std::size_t fillNodata(std::vector<float>& heightsM, const std::vector<std::uint8_t>& valid, int width, int height);

/// Quantised grid (heights only; colours left empty) for an elevation grid.
TerrainGrid quantiseElevation(const ElevationGrid& elevation);

}  // namespace fieldcast::core
