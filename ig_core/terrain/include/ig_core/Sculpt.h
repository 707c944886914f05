#pragma once
// Sculpting a voxel model from three photographs (ig_core/README.md, "Sculpted models"): the
// object's side, front and top, each an orthographic view with its background keyed out. A block
// of voxels is carved by the three silhouettes (reconstruction from projection: a voxel stays when
// it lies inside all three) and each surviving voxel takes its colour from the photograph that
// looks at its open face.
//
// The views, in the model's axes (VoxelSolid.h: x right, y front, z up):
//   side  — seen from the object's right: the image's left is its back, its right the front;
//   front — seen from in front: the image's left is the object's right;
//   top   — seen from above: the image's top is the object's front, its left the object's left.
// The back and the left side look like the front and the right (three photographs cannot tell).

#include <ig_core/VoxelSolid.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace fieldcast::core {

/// How a photograph's background is told from the object.
struct BackgroundKey {
  /// Background: pixels within `tolerance` (largest channel difference) of this colour, RGB8 with
  /// R in the low byte. Without it the image's alpha channel decides (alpha < 128: background).
  std::optional<std::uint32_t> keyRgb;
  int tolerance = 24;
};

/// A photograph and which of its pixels are the object. Row-major from the top-left.
struct Silhouette {
  int width = 0, height = 0;
  std::vector<std::uint32_t> rgba;   ///< RGBA8, R in the low byte
  std::vector<std::uint8_t> inside;  ///< 1: the object, 0: background
};

/// Keys `rgba` (alpha 255 where the image had none) by `key`. Throws std::invalid_argument when
/// the sizes do not match.
Silhouette keySilhouette(int width, int height, std::vector<std::uint32_t> rgba, const BackgroundKey& key);

/// Reads an image (any format OpenImageIO reads: PNG, TIFF, JPEG …) and keys it. Throws
/// std::runtime_error naming the file when it cannot be read, has no alpha channel and no key
/// colour is given, or shows no object.
Silhouette readSilhouette(const std::filesystem::path& path, const BackgroundKey& key);

struct SculptViews {
  Silhouette side, front, top;
};

/// A sculpted solid and what went into it.
struct SculptResult {
  VoxelSolid solid;
  double widthM = 0.0, depthM = 0.0, heightM = 0.0;  ///< the object's size the photographs give
  double topAspectError = 0.0;                       ///< the top view's aspect against the side's and front's, relative
  /// Surface voxels coloured from each photograph (side, front, top), and hidden voxels (which
  /// take the side's colour)
  std::size_t fromSide = 0, fromFront = 0, fromTop = 0, hidden = 0;
};

/// The largest relative disagreement of the top view's aspect with the side's and front's.
inline constexpr double kMaxTopAspectError = 0.1;

/// Carves the object whose height is `heightM`: each photograph is cropped to its silhouette's
/// bounding box, the side and front scaled to the height, the top stretched over the width and
/// depth they give; voxels kSolidVoxelM on a side, a voxel inside a view when at least half its
/// projection is. Throws std::invalid_argument for a height out of 0.5 m … 128 m, a view without
/// an object, a top view whose aspect disagrees by more than kMaxTopAspectError, or an object of
/// more than 256 voxels a side.
SculptResult sculptFromSilhouettes(const SculptViews& views, double heightM);

}  // namespace fieldcast::core
