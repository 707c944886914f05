// The depth-mesh warp. For each node q of a raster grid, find the frame pixel p whose point (its
// ray lengthened to the range image's distance) the field's camera sees at q: solve F(p) = q,
// where F lifts p through the range image and projects it into the field. Newton's method with
// F's Jacobian by finite differences, reused from step to step and node to node while it keeps
// halving the residual (one evaluation of F per step), measured afresh when it does not, with
// the step then halved until the residual falls (a step across a depth edge can overshoot).
// A node starts from its left neighbour's parallax or, when the last field warped the same
// frame, from that field's solution moved on by its motion since the field before, so most
// nodes need one evaluation. Where no frame point projects to q (a surface hidden in the frame:
// a disocclusion behind a ridge), Newton cannot converge and the node keeps the candidate that
// came closest. Optionally, cells the bilinear map misses at their centre are refined.
#include <prp_warp/Warps.h>

#include <fieldcast/Conventions.h>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace fieldcast::warp {
namespace {

constexpr int kMaxIterations = 8;
constexpr double kSolvedPx = 0.02;      // residual in raster pixels that counts as exact
constexpr double kTrustPx = 0.1;        // residual below which one Newton step is taken unchecked ...
constexpr double kTrustedStepPx = 1.0;  // ... when the step is shorter than this (frame pixels)
constexpr double kSmoothRange = 1.5;    // a 2 × 2 range neighbourhood within this ratio is one surface
constexpr double kMinDepth = 1e-6;

/// F: frame pixel → field raster pixel through the range image.
class FrameToField {
 public:
  FrameToField(const Frame& frame, const Pose& fieldPose, const OutputGeometry& g) noexcept
      : mFrame(frame.intrinsics),
        mRaster(g.raster),
        mRange(frame.rangeM.data()),
        mRotation(worldToCameraRotation(fieldPose) * glm::transpose(worldToCameraRotation(frame.pose))),
        mTranslation(worldToCameraRotation(fieldPose) * (frame.pose.positionM - fieldPose.positionM)) {}

  /// Where the field sees the point of frame pixel `p`; nothing for an unrendered pixel or a
  /// point behind the field's camera.
  std::optional<glm::dvec2> operator()(glm::dvec2 p) const noexcept {
    const double range = rangeAt(p);
    if (!(range > 0.0)) return std::nullopt;  // unrendered (0) or NaN
    const glm::dvec3 ray{(p.x - mFrame.cxPx) / mFrame.fxPx, -(p.y - mFrame.cyPx) / mFrame.fyPx, 1.0};
    // Range is the distance along the ray; the sky moves as a direction
    const glm::dvec3 c = std::isinf(range) ? mRotation * ray
                                           : mRotation * (ray * (range / std::sqrt(glm::dot(ray, ray)))) + mTranslation;
    if (!(c.z > kMinDepth)) return std::nullopt;
    return glm::dvec2{mRaster.cxPx + mRaster.fxPx * c.x / c.z, mRaster.cyPx - mRaster.fyPx * c.y / c.z};
  }

 private:
  /// The range at continuous frame pixel `p` (clamped to the frame): bilinear within one surface,
  /// the nearest pixel's across a depth edge or next to the sky.
  double rangeAt(glm::dvec2 p) const noexcept {
    const int w = mFrame.widthPx, h = mFrame.heightPx;
    const double x = std::clamp(p.x - 0.5, 0.0, w - 1.0);  // pixel-centre coordinates
    const double y = std::clamp(p.y - 0.5, 0.0, h - 1.0);
    if (!(x == x && y == y)) return 0.0;  // NaN
    const int i0 = static_cast<int>(x), j0 = static_cast<int>(y);
    const int i1 = std::min(i0 + 1, w - 1), j1 = std::min(j0 + 1, h - 1);
    const double fx = x - i0, fy = y - j0;
    auto at = [&](int i, int j) noexcept {
      return static_cast<double>(mRange[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + i]);
    };
    const double r00 = at(i0, j0), r10 = at(i1, j0), r01 = at(i0, j1), r11 = at(i1, j1);
    const double lo = std::min({r00, r10, r01, r11}), hi = std::max({r00, r10, r01, r11});
    if (lo > 0.0 && std::isfinite(hi) && hi <= kSmoothRange * lo) {
      return (1 - fy) * ((1 - fx) * r00 + fx * r10) + fy * ((1 - fx) * r01 + fx * r11);
    }
    return at(fx < 0.5 ? i0 : i1, fy < 0.5 ? j0 : j1);
  }

  Intrinsics mFrame;
  Intrinsics mRaster;
  const float* mRange;
  glm::dmat3 mRotation;
  glm::dvec3 mTranslation;
};

bool finite(glm::dvec2 p) noexcept { return std::isfinite(p.x) && std::isfinite(p.y); }

/// F's Jacobian at a point, from finite differences.
struct Jacobian {
  glm::dvec2 dFdx{0.0}, dFdy{0.0};
  bool valid = false;

  static Jacobian at(const FrameToField& toField, glm::dvec2 p, glm::dvec2 seen) noexcept {
    constexpr double kStepPx = 0.5;
    const auto dx = toField(p + glm::dvec2{kStepPx, 0.0});
    const auto dy = toField(p + glm::dvec2{0.0, kStepPx});
    if (!dx || !dy) return {};
    return {(*dx - seen) / kStepPx, (*dy - seen) / kStepPx, true};
  }

  /// The step d with J·d = e; NaN where J is singular.
  glm::dvec2 solve(glm::dvec2 e) const noexcept {
    const double det = dFdx.x * dFdy.y - dFdy.x * dFdx.y;
    if (!valid || !(std::abs(det) > 1e-6)) return {Homography::kNan, Homography::kNan};
    return {(dFdy.y * e.x - dFdy.x * e.y) / det, (dFdx.x * e.y - dFdx.y * e.x) / det};
  }
};

/// Solves F(p) = q for one raster point at a time.
class NodeSolver {
 public:
  struct Solution {
    glm::dvec2 framePx{0.0};
    bool solved = false;  ///< residual under kSolvedPx; otherwise the closest candidate
  };

  NodeSolver(const Frame& frame, const Pose& fieldPose, const OutputGeometry& g) noexcept
      : mToField(frame, fieldPose, g), mRotation(rotationHomography(frame, fieldPose, g)) {}

  /// F(p): where the field sees the point of frame pixel p.
  std::optional<glm::dvec2> toField(glm::dvec2 framePx) const noexcept { return mToField(framePx); }

  /// H(q): where a camera that only turned would sample raster point q.
  glm::dvec2 rotationOnly(glm::dvec2 q) const noexcept { return mRotation(q); }

  /// The frame pixel F maps to raster point `q`, starting from `guess` (the rotation-only
  /// point when the guess is unusable).
  Solution solve(glm::dvec2 q, glm::dvec2 guess) noexcept {
    const glm::dvec2 target = mRotation(q);
    Solution best{target, false};  // the rotation-only map when nothing better is found
    double bestResidual = std::numeric_limits<double>::infinity();
    glm::dvec2 p = guess;
    auto seen = finite(p) ? mToField(p) : std::nullopt;
    if (!seen) {
      p = target;
      seen = mToField(p);
    }
    for (int it = 0; seen && it < kMaxIterations; ++it) {
      const double residual = glm::length(*seen - q);
      if (residual < bestResidual) {
        bestResidual = residual;
        best.framePx = p;
      }
      if (residual < kSolvedPx) break;
      // The Jacobian of the last step (or node) first: it costs no evaluation, and on smooth
      // terrain it halves the residual at least
      const glm::dvec2 quick = mJacobian.solve(q - *seen);
      if (residual < kTrustPx && finite(quick) && glm::length(quick) < kTrustedStepPx) {
        // Close enough for the linearisation: the step's own error is second order in the
        // residual, far below the solver's tolerance, so it is taken without checking (a step
        // longer than a pixel for so small a residual means a Jacobian from another surface)
        best = {p + quick, true};
        return best;
      }
      if (finite(quick)) {
        const auto next = mToField(p + quick);
        if (next && glm::length(*next - q) < 0.5 * residual) {
          p += quick;
          seen = next;
          continue;
        }
      }
      // Measure it here; where it is singular or undefined (a frame edge), take the
      // rotation-only step H(q) − H(F(p)). Halve the step until the residual falls.
      mJacobian = Jacobian::at(mToField, p, *seen);
      glm::dvec2 step = mJacobian.solve(q - *seen);
      if (!finite(step)) step = target - mRotation(*seen);
      if (!finite(step)) break;
      bool improved = false;
      for (double scale = 1.0; scale >= 0.125 && !improved; scale *= 0.5) {
        const auto next = mToField(p + scale * step);
        if (next && glm::length(*next - q) < residual) {
          p += scale * step;
          seen = next;
          improved = true;
        }
      }
      if (!improved) break;
    }
    best.solved = bestResidual < kSolvedPx;
    return best;
  }

 private:
  FrameToField mToField;
  Homography mRotation;
  Jacobian mJacobian;  // of the last step, carried to the next node
};

}  // namespace

MeshWarp::MeshWarp(int rasterWidthPx, int rasterHeightPx, ResampleKernel kernel, MeshOptions options)
    : Warp(rasterWidthPx, rasterHeightPx),
      mKernel(kernel),
      mOptions(options),
      mScratch(rasterWidthPx),
      mMap(rasterWidthPx, rasterHeightPx, std::max(1, options.spacingPx)),
      mFallback(rasterWidthPx, rasterHeightPx, kernel),
      mBeforeX(static_cast<std::size_t>(mMap.columns()) * static_cast<std::size_t>(mMap.rows())),
      mBeforeY(mBeforeX.size()) {}

bool MeshWarp::solveNodes(const Frame& frame, const Pose& fieldPose, const OutputGeometry& g) noexcept {
  NodeSolver solver(frame, fieldPose, g);
  mUnsolvedNodes = 0;
  mMap.clearRefinement();
  const bool sameFrame =
      mHaveMap && !mUsedFallback && frame.frameNumber == mLastFrameNumber && frame.poseTime == mLastFramePoseTime;
  const bool sameFrameTwice = sameFrame && mSameFrameBefore;
  mSameFrameBefore = sameFrame;
  mLastFrameNumber = frame.frameNumber;
  mLastFramePoseTime = frame.poseTime;
  // The grid, row by row; each node starts from its left neighbour's parallax (the row's first
  // from the node above)
  glm::dvec2 parallax{0.0, 0.0};
  for (int l = 0; l < mMap.rows(); ++l) {
    for (int k = 0; k < mMap.columns(); ++k) {
      const glm::dvec2 q{static_cast<double>(mMap.nodeXPx(k)), static_cast<double>(mMap.nodeYPx(l))};
      const glm::dvec2 target = solver.rotationOnly(q);
      if (!finite(target)) return false;  // the node looks behind the frame's camera
      if (k == 0 && l > 0) {
        parallax = glm::dvec2{mMap.frameX(0, l - 1), mMap.frameY(0, l - 1)} -
                   solver.rotationOnly(glm::dvec2{0.0, static_cast<double>(mMap.nodeYPx(l - 1))});
        if (!finite(parallax)) parallax = {0.0, 0.0};
      }
      // When the last field warped the same frame, its solution moved on by its own motion since
      // the field before (the pose moves smoothly from field to field)
      glm::dvec2 guess = target + parallax;
      const std::size_t index = static_cast<std::size_t>(l) * static_cast<std::size_t>(mMap.columns()) + k;
      if (sameFrame) {
        const glm::dvec2 last{mMap.frameX(k, l), mMap.frameY(k, l)};
        guess = sameFrameTwice ? 2.0 * last - glm::dvec2{mBeforeX[index], mBeforeY[index]} : last;
        mBeforeX[index] = last.x;
        mBeforeY[index] = last.y;
      }
      const NodeSolver::Solution node = solver.solve(q, guess);
      mUnsolvedNodes += node.solved ? 0 : 1;
      mMap.frameX(k, l) = static_cast<float>(node.framePx.x);
      mMap.frameY(k, l) = static_cast<float>(node.framePx.y);
      parallax = node.framePx - target;
    }
  }
  // Refine the cells whose centre the bilinear map misses (the horizon, a silhouette)
  if (!(mOptions.refineAbovePx > 0.0)) return true;
  for (int l = 0; l + 1 < mMap.rows(); ++l) {
    for (int k = 0; k + 1 < mMap.columns(); ++k) {
      const glm::dvec2 centre{0.5 * (mMap.nodeXPx(k) + mMap.nodeXPx(k + 1)),
                              0.5 * (mMap.nodeYPx(l) + mMap.nodeYPx(l + 1))};
      // One evaluation of F: where the field sees the point the bilinear map samples
      const auto seen = solver.toField(mMap(centre));
      if (seen && !(glm::length(*seen - centre) > mOptions.refineAbovePx)) continue;
      mMap.refine(k, l);
      for (int j = 0; j < MeshMap::kSubNodes; ++j)
        for (int i = 0; i < MeshMap::kSubNodes; ++i) {
          const bool corner = (i == 0 || i == MeshMap::kSubdivision) && (j == 0 || j == MeshMap::kSubdivision);
          if (corner) continue;  // the cell's own nodes
          const glm::dvec2 q = mMap.subNodePx(k, l, i, j);
          const NodeSolver::Solution sub = solver.solve(q, {mMap.subX(k, l, i, j), mMap.subY(k, l, i, j)});
          mUnsolvedNodes += sub.solved ? 0 : 1;
          mMap.subX(k, l, i, j) = static_cast<float>(sub.framePx.x);
          mMap.subY(k, l, i, j) = static_cast<float>(sub.framePx.y);
        }
    }
  }
  return true;
}

WarpResult MeshWarp::doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                            FieldRows out) noexcept {
  const auto framePixels = static_cast<std::size_t>(frame.intrinsics.widthPx) * frame.intrinsics.heightPx;
  FallbackReason reason = FallbackReason::None;
  const OutputGeometry g = OutputGeometry::of(frame, rasterWidthPx(), rasterHeightPx());
  if (!frame.hasRange() || frame.rangeM.size() != framePixels) {
    reason = FallbackReason::NoRange;
  } else if (!solveNodes(frame, fieldPose, g)) {
    reason = FallbackReason::Degenerate;
  }
  mUsedFallback = reason != FallbackReason::None;
  if (mUsedFallback) {
    WarpResult r = mFallback.warp(frame, pixels, fieldPose, parity, out);
    r.fellBack = true;
    r.fallbackReason = reason;
    return r;
  }
  mHaveMap = true;
  const std::uint32_t violations = mKernel == ResampleKernel::Fast
                                       ? resampleMeshFast(pixels, mMap, parity, rasterHeightPx(), out, mScratch)
                                       : resampleMeshReference(pixels, mMap, parity, rasterHeightPx(), out);
  return {WarpStatus::Ok, violations, false};
}

std::optional<glm::dvec2> MeshWarp::sourcePx(glm::dvec2 rasterPx) const noexcept {
  if (mUsedFallback) return mFallback.sourcePx(rasterPx);
  if (!mHaveMap) return std::nullopt;
  return mMap(rasterPx);
}

}  // namespace fieldcast::warp
