#pragma once
// Voxel colour: baked procedurally from the heights (palette by elevation and slope, fine noise,
// hillshade from a configurable sun), or draped from an orthophoto. Colour or grey-level.

#include <ig_core/TerrainView.h>

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace fieldcast::core {

/// Colour or grey-level output (grey voxels are stored R = G = B).
enum class ColourOutput : std::uint8_t { Colour, Grey };

/// Procedural colour: how the palette is lit and textured.
struct ProceduralColourOptions {
  double sunAzimuthDeg = 315.0;   ///< where the light comes from, clockwise from north (NW: maps' convention)
  double sunElevationDeg = 40.0;  ///< above the horizon
  double hillshade = 0.7;         ///< 0: flat light, 1: full Lambert shading (flat ground keeps its palette colour)
  double noise = 0.10;            ///< amplitude of the fine brightness noise (fraction of brightness)
  double seaLevelM = 0.0;         ///< voxels at or below are water when no water mask is given
  std::uint32_t seed = 1;
  ColourOutput output = ColourOutput::Colour;
  int threads = 0;  ///< 0: every core
};

/// What the procedural colour painted a voxel as: what the built-in terrain is furnished by
/// (forests on Forest, hedgerows on FieldEdge).
enum class LandCover : std::uint8_t {
  Water,
  Open,       ///< meadow, sand, rock, snow, or a blend
  Field,      ///< inside a field of the lowland patchwork
  FieldEdge,  ///< a field's west or south boundary voxel
  Forest,
};

/// Bakes a colour for every voxel of `geometry` from its quantised heights (W×H, row-major).
/// `waterDepthM` is optional (empty, or W×H): 0 marks land, n > 0 water about n metres deep.
/// With `cover`, also says what each voxel was painted as (W×H). Throws std::invalid_argument
/// when sizes do not match.
std::vector<std::uint32_t> bakeProceduralColour(const TerrainGeometry& geometry, std::span<const std::uint16_t> heightQ,
                                                std::span<const std::uint8_t> waterDepthM,
                                                const ProceduralColourOptions& options,
                                                std::vector<LandCover>* cover = nullptr);

/// Where an orthophoto lies: world position of its top-left pixel corner and pixel size.
/// Left unset, the image is stretched over the whole grid (its GeoTIFF tags are used when present).
struct OrthophotoPlacement {
  bool fromFile = true;       ///< use the image's GeoTIFF tags when it has them, else stretch
  bool stretchToGrid = true;  ///< used when there are no tags (or fromFile is false)
  double topLeftXM = 0.0;     ///< world x of the image's left edge (when not stretched)
  double topLeftYM = 0.0;     ///< world y of the image's top edge
  double pixelSizeXM = 1.0;   ///< metres per pixel east
  double pixelSizeYM = 1.0;   ///< metres per pixel south (positive)
};

/// Resamples an orthophoto (any image OpenImageIO reads; 1, 3 or 4 channels) onto the voxel
/// grid with bilinear filtering (box-averaged when the photo is finer than the grid). Voxels outside
/// the photo get `outside`. Throws std::runtime_error naming the file when it cannot be read.
std::vector<std::uint32_t> drapeOrthophoto(const std::filesystem::path& image, const TerrainGeometry& geometry,
                                           const OrthophotoPlacement& placement, ColourOutput output,
                                           std::uint32_t outside = 0xFF808080u, int threads = 0);

/// Packs 8-bit channels as R | G<<8 | B<<16 | A<<24.
constexpr std::uint32_t packRgba(std::uint32_t r, std::uint32_t g, std::uint32_t b, std::uint32_t a = 255) noexcept {
  return r | (g << 8) | (b << 16) | (a << 24);
}

}  // namespace fieldcast::core
