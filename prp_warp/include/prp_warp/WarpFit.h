#pragma once
// The fits behind the warps (DESIGN.md §3): project the frame's control points into the field's
// pose, then solve the map from raster pixels to frame pixels by least squares.

#include <prp_warp/OutputGeometry.h>
#include <prp_warp/WarpMaps.h>

#include <fieldcast/Frame.h>
#include <fieldcast/Intrinsics.h>
#include <fieldcast/Pose.h>

#include <glm/vec2.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <span>

namespace fieldcast::warp {

/// Control points used per fit at most; further points of a frame are ignored.
inline constexpr int kMaxControlPoints = 64;

/// Control points as pairs (where the field pose sees them, where the frame recorded them).
struct Correspondences {
  std::array<glm::dvec2, kMaxControlPoints> rasterPx{};  ///< projection into the field's raster
  std::array<glm::dvec2, kMaxControlPoints> framePx{};   ///< the fixed control pixel of the frame
  int count = 0;                                         ///< usable pairs
  int surfaceCount = 0;  ///< of which surface points (the rest are sky points at infinity)
};

/// Projects the control points of `frame` into the raster of `geometry` at `fieldPose`. A point
/// is usable when it is in front of the camera and projects within four raster half-sizes of
/// the centre (beyond, grazing points would dominate the fit). Sky points project as
/// directions. RT-safe.
Correspondences projectControlPoints(const Frame& frame, const Pose& fieldPose,
                                     const OutputGeometry& geometry) noexcept;

/// Least-squares quadratic map rasterPx → framePx over the pairs (Householder QR with column
/// pivoting on coordinates normalised about `centrePx` by `halfSizePx`). Nothing when fewer than
/// six pairs or the monomials are rank-deficient (e.g. collinear points). RT-safe, no allocation.
std::optional<QuadraticMap> fitQuadratic(std::span<const glm::dvec2> rasterPx, std::span<const glm::dvec2> framePx,
                                         glm::dvec2 centrePx, double halfSizePx) noexcept;

/// Least-squares homography rasterPx → framePx (normalised DLT, smallest eigenvector of AᵀA).
/// Nothing when fewer than four pairs or degenerate. RT-safe, no allocation.
std::optional<Homography> fitHomography(std::span<const glm::dvec2> rasterPx,
                                        std::span<const glm::dvec2> framePx) noexcept;

/// The exact map for a camera that only rotated from the frame's pose to `fieldPose` (every
/// point at infinity): H = K_frame · R_frame · R_fieldᵀ · K_raster⁻¹. RT-safe.
Homography rotationHomography(const Frame& frame, const Pose& fieldPose, const OutputGeometry& geometry) noexcept;

/// How a field's quadratic fit went.
enum class FitOutcome : std::uint8_t {
  Quadratic,           ///< least-squares quadratic over ≥ 6 usable points
  FallbackFewPoints,   ///< fewer than six usable points: rotation-only homography
  FallbackAllSky,      ///< every usable point at infinity: rotation-only homography (exact there)
  FallbackDegenerate,  ///< rank-deficient point layout: rotation-only homography
};

/// The quadratic map of a field, or the rotation-only homography when the fit cannot be trusted.
struct QuadraticFit {
  FitOutcome outcome = FitOutcome::Quadratic;
  QuadraticMap quadratic;  ///< valid when outcome == Quadratic
  Homography homography;   ///< valid otherwise
  int usablePoints = 0;
  bool fellBack() const noexcept { return outcome != FitOutcome::Quadratic; }
  /// Frame pixel the map samples for raster pixel `rasterPx`. RT-safe.
  glm::dvec2 operator()(glm::dvec2 rasterPx) const noexcept {
    return fellBack() ? homography(rasterPx) : quadratic(rasterPx);
  }
};

/// The whole fit for one field (projection, QR, fallback). RT-safe, no allocation.
QuadraticFit fitFieldQuadratic(const Frame& frame, const Pose& fieldPose, const OutputGeometry& geometry) noexcept;

}  // namespace fieldcast::warp
