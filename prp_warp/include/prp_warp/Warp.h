#pragma once
// The common interface of the field warps (DESIGN.md §3): frame hold, rotation-only
// reprojection, quadratic, homography, depth mesh and per-pixel 3D warp all turn (frame, pose at the field's time) into
// the rows of one field, so their quality and cost can be compared on the same flight.

#include <fieldcast/Field.h>
#include <fieldcast/Frame.h>
#include <fieldcast/Image.h>
#include <fieldcast/Pose.h>
#include <prp_warp/FieldRows.h>

#include <glm/vec2.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

namespace fieldcast::warp {

/// Which warp turns frames into fields.
enum class WarpKind : std::uint8_t {
  Hold,        ///< no warp: the frame's display window as it is (the baseline)
  Quadratic,   ///< least-squares quadratic through the control points (the design's warp)
  Homography,  ///< least-squares perspective homography through the control points
  Range3d,     ///< per-pixel 3D warp of the range image (forward splat, depth test, hole fill)
  Rotation,    ///< the rotation-only homography, every point at infinity (VR's asynchronous timewarp)
  Mesh,        ///< depth mesh: a grid of raster nodes reprojected exactly through the range image, bilinear between
};

/// Name as written in configuration ("hold", "quadratic", "homography", "range3d", "rotation", "mesh").
constexpr std::string_view toString(WarpKind kind) noexcept {
  switch (kind) {
    case WarpKind::Hold: return "hold";
    case WarpKind::Quadratic: return "quadratic";
    case WarpKind::Homography: return "homography";
    case WarpKind::Range3d: return "range3d";
    case WarpKind::Rotation: return "rotation";
    case WarpKind::Mesh: return "mesh";
  }
  return "?";
}

/// Parses a configuration name; nothing when unknown.
std::optional<WarpKind> warpKindFromString(std::string_view name) noexcept;

/// Outcome of warping one field.
enum class WarpStatus : std::uint8_t {
  Ok,
  BadFrame,   ///< frame empty, wrong format, inconsistent sizes: the output was left untouched
  BadOutput,  ///< the output image has the wrong shape or format for the field
};

/// Why a warp used its fallback (the rotation-only homography, or the quadratic for a warp that
/// needs the range image).
enum class FallbackReason : std::uint8_t {
  None,
  FewPoints,   ///< too few usable control points for the fit
  AllSky,      ///< every usable control point at infinity
  Degenerate,  ///< the points' layout left the fit rank-deficient
  NoRange,     ///< a 3D or mesh warp was given a frame without its range image
};

/// What one field's warp did.
struct WarpResult {
  WarpStatus status = WarpStatus::Ok;
  /// Output pixels whose source fell outside the frame (outside its footprint, for a rolled one)
  std::uint32_t marginViolations = 0;
  bool fellBack = false;  ///< the warp could not be fitted and used its fallback (counted by the caller)
  FallbackReason fallbackReason = FallbackReason::None;  ///< why, when fellBack
};

/// A field warp. Each instance serves one raster size and one thread; it owns its scratch, so
/// warp() allocates nothing.
class Warp {
 public:
  /// For an output raster `rasterWidthPx` × `rasterHeightPx` (the whole interlaced frame).
  Warp(int rasterWidthPx, int rasterHeightPx) noexcept
      : mRasterWidthPx(rasterWidthPx), mRasterHeightPx(rasterHeightPx) {}
  virtual ~Warp() = default;
  Warp(const Warp&) = delete;
  Warp& operator=(const Warp&) = delete;

  virtual WarpKind kind() const noexcept = 0;

  /// Warps frame `frame` to the pose `fieldPose` of a field and writes the rows of `parity` to
  /// `out` (raster width × fieldRowCount rows, the frame's pixel format; an image, or a sink
  /// that takes them a piece at a time). `pixels` is the image
  /// sampled: the frame's own, or a same-sized filtered copy of it. RT-safe, noexcept.
  WarpResult warp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                  FieldRows out) noexcept;
  /// warp() sampling the frame's own image. RT-safe.
  WarpResult warp(const Frame& frame, const Pose& fieldPose, FieldParity parity, FieldRows out) noexcept {
    return warp(frame, frame.image, fieldPose, parity, out);
  }

  /// Frame pixel (continuous, margin included) the last warp sampled for raster pixel `rasterPx`;
  /// nothing before the first warp or where it had no sample (e.g. a 3D-warp pixel not on the
  /// last field's rows). This is the sampling map an evaluation compares with the truth.
  virtual std::optional<glm::dvec2> sourcePx(glm::dvec2 rasterPx) const noexcept = 0;

  int rasterWidthPx() const noexcept { return mRasterWidthPx; }
  int rasterHeightPx() const noexcept { return mRasterHeightPx; }

 protected:
  /// The warp proper, called with validated shapes. RT-safe.
  virtual WarpResult doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                            FieldRows out) noexcept = 0;

 private:
  /// The pixels of the field just warped whose source (sourcePx) lies outside `footprint`, row by
  /// row: three map evaluations (the ends and the middle) when all are inside, and a bisection at
  /// each boundary otherwise. A row's sources are taken to leave the convex footprint at most once
  /// at each end, or once around the middle: exact for the rotation and homography (straight rows)
  /// and for the quadratic's gently bent ones; for the 3D and mesh warps, whose maps follow the
  /// depth, a count to a boundary per row side. A pixel with no sample reads nothing: inside. RT-safe.
  std::uint32_t countOutsideFootprint(const FrameFootprint& footprint, FieldParity parity, int rows) const noexcept;

  int mRasterWidthPx;
  int mRasterHeightPx;
};

/// True when the warp reads the frame's per-pixel range, so the renderer must produce it.
constexpr bool needsRangeImage(WarpKind kind) noexcept { return kind == WarpKind::Range3d || kind == WarpKind::Mesh; }

/// A warp of `kind` for a raster `rasterWidthPx` × `rasterHeightPx`; all its scratch is
/// allocated here. Throws std::invalid_argument for a raster smaller than 2 × 2.
std::unique_ptr<Warp> makeWarp(WarpKind kind, int rasterWidthPx, int rasterHeightPx);

}  // namespace fieldcast::warp
