#pragma once
// The six field warps behind the Warp interface. Each file in src/ implements one of them.

#include <prp_warp/OutputGeometry.h>
#include <prp_warp/Resample.h>
#include <prp_warp/Warp.h>
#include <prp_warp/WarpFit.h>
#include <prp_warp/WarpMaps.h>

#include <vector>

namespace fieldcast::warp {

/// No warp: shows the frame's display window scaled to the raster (the baseline).
class HoldWarp final : public Warp {
 public:
  HoldWarp(int rasterWidthPx, int rasterHeightPx);
  WarpKind kind() const noexcept override { return WarpKind::Hold; }
  std::optional<glm::dvec2> sourcePx(glm::dvec2 rasterPx) const noexcept override;

 protected:
  WarpResult doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                    FieldRows out) noexcept override;

 private:
  RowScratch mScratch;
  std::optional<QuadraticMap> mLastMap;
};

/// Which resampling kernel a QuadraticWarp uses.
enum class ResampleKernel : std::uint8_t {
  Fast,       ///< the map in lanes + fixed-point bilinear (production)
  Reference,  ///< per-pixel evaluation, double precision (the test oracle)
};

/// The design's warp: a least-squares quadratic through the control points projected into the
/// field's pose (roll included), falling back to the rotation-only homography.
class QuadraticWarp final : public Warp {
 public:
  QuadraticWarp(int rasterWidthPx, int rasterHeightPx, ResampleKernel kernel = ResampleKernel::Fast);
  WarpKind kind() const noexcept override { return WarpKind::Quadratic; }
  std::optional<glm::dvec2> sourcePx(glm::dvec2 rasterPx) const noexcept override;
  /// The fit of the last field.
  const QuadraticFit& lastFit() const noexcept { return mFit; }

 protected:
  WarpResult doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                    FieldRows out) noexcept override;

 private:
  ResampleKernel mKernel;
  RowScratch mScratch;
  QuadraticFit mFit;
  bool mHaveFit = false;
};

/// A least-squares homography through the control points projected into the field's pose: the
/// exact map for a planar scene or a pure rotation. Falls back to the rotation-only homography
/// with fewer than four usable points.
class HomographyWarp final : public Warp {
 public:
  HomographyWarp(int rasterWidthPx, int rasterHeightPx);
  WarpKind kind() const noexcept override { return WarpKind::Homography; }
  std::optional<glm::dvec2> sourcePx(glm::dvec2 rasterPx) const noexcept override;
  const Homography& lastHomography() const noexcept { return mMap; }

 protected:
  WarpResult doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                    FieldRows out) noexcept override;

 private:
  RowScratch mScratch;
  Homography mMap;
  bool mHaveMap = false;
};

/// Rotation-only reprojection: the exact map for a camera that turned but did not move, every
/// point taken at infinity. What VR runtimes call asynchronous timewarp: the baseline a reader
/// knows. Never falls back.
class RotationWarp final : public Warp {
 public:
  RotationWarp(int rasterWidthPx, int rasterHeightPx);
  WarpKind kind() const noexcept override { return WarpKind::Rotation; }
  std::optional<glm::dvec2> sourcePx(glm::dvec2 rasterPx) const noexcept override;

 protected:
  WarpResult doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                    FieldRows out) noexcept override;

 private:
  RowScratch mScratch;
  std::optional<Homography> mMap;
};

/// How a MeshWarp lays its nodes.
struct MeshOptions {
  int spacingPx = 16;          ///< raster pixels between grid nodes
  double refineAbovePx = 0.0;  ///< refine a cell whose centre the bilinear map misses by more (raster px); 0: never
};

/// The depth-mesh warp: a grid of raster nodes (every `spacingPx`), each solved exactly for the
/// frame pixel whose range-image point the field's camera sees there, and the frame resampled
/// through the bilinear map between the nodes. The streaming cost of the quadratic with the
/// parallax of the 3D warp at the nodes. Optionally, cells the bilinear map misses at their
/// centre (the horizon, a ridge's silhouette) are refined into sub-cells with nodes of their own.
/// Frames without a range image fall back to the quadratic.
class MeshWarp final : public Warp {
 public:
  MeshWarp(int rasterWidthPx, int rasterHeightPx, ResampleKernel kernel = ResampleKernel::Fast,
           MeshOptions options = {});
  WarpKind kind() const noexcept override { return WarpKind::Mesh; }
  std::optional<glm::dvec2> sourcePx(glm::dvec2 rasterPx) const noexcept override;
  /// The node map of the last field.
  const MeshMap& lastMap() const noexcept { return mMap; }
  /// Nodes of the last field with no exact solution (the raster point sees a surface the frame
  /// did not: a disocclusion behind a ridge); each took its closest candidate.
  int lastUnsolvedNodes() const noexcept { return mUnsolvedNodes; }

 protected:
  WarpResult doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                    FieldRows out) noexcept override;

 private:
  bool solveNodes(const Frame& frame, const Pose& fieldPose, const OutputGeometry& g) noexcept;

  ResampleKernel mKernel;
  MeshOptions mOptions;
  RowScratch mScratch;
  MeshMap mMap;
  QuadraticWarp mFallback;
  bool mUsedFallback = false;
  bool mHaveMap = false;
  int mUnsolvedNodes = 0;
  std::uint64_t mLastFrameNumber = 0;  // the frame the map was solved for: its nodes start the next field's
  TimePoint mLastFramePoseTime{};
  bool mSameFrameBefore = false;           // the last field's frame was also the one before's
  std::vector<double> mBeforeX, mBeforeY;  // the grid's nodes one field before the map's
};

/// Post-rendering 3D warping (after Mark, McMillan & Bishop 1997): every frame pixel with a range
/// is lifted to 3D, projected into the field's pose and splatted with a depth test onto the
/// field's rows; each written raster pixel records the frame position it extrapolates to, holes
/// are filled from the farther neighbour, and the frame is then sampled bilinearly through that
/// per-pixel map. Frames without a range image fall back to the quadratic warp.
class Range3dWarp final : public Warp {
 public:
  Range3dWarp(int rasterWidthPx, int rasterHeightPx);
  WarpKind kind() const noexcept override { return WarpKind::Range3d; }
  /// The per-pixel map is defined at pixel centres: this returns the source of the centre of
  /// the raster pixel containing `rasterPx`, on the last field's rows only.
  std::optional<glm::dvec2> sourcePx(glm::dvec2 rasterPx) const noexcept override;

 protected:
  WarpResult doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                    FieldRows out) noexcept override;

 private:
  void splat(const Frame& frame, const Pose& fieldPose, const OutputGeometry& g, FieldParity parity) noexcept;
  void fillHoles(FieldParity parity, const OutputGeometry& g) noexcept;
  // Raster row `emptyRow` takes filled row `filledRow`'s map, moved by their distance
  void continueRow(int filledRow, int emptyRow, const OutputGeometry& g) noexcept;

  std::vector<float> mDepth;        // per raster pixel: depth of the sample kept
  std::vector<float> mMapX, mMapY;  // per raster pixel: frame pixel it samples
  QuadraticWarp mFallback;
  bool mUsedFallback = false;
  std::optional<FieldParity> mLastParity;
};

}  // namespace fieldcast::warp
