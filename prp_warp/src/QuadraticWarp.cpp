// The design's warp (DESIGN.md §3): fit the quadratic for the field's pose, resample through it.
#include <prp_warp/Warps.h>

namespace fieldcast::warp {
namespace {

FallbackReason fallbackReasonOf(FitOutcome outcome) noexcept {
  switch (outcome) {
    case FitOutcome::Quadratic: return FallbackReason::None;
    case FitOutcome::FallbackFewPoints: return FallbackReason::FewPoints;
    case FitOutcome::FallbackAllSky: return FallbackReason::AllSky;
    case FitOutcome::FallbackDegenerate: return FallbackReason::Degenerate;
  }
  return FallbackReason::Degenerate;
}

}  // namespace

QuadraticWarp::QuadraticWarp(int rasterWidthPx, int rasterHeightPx, ResampleKernel kernel)
    : Warp(rasterWidthPx, rasterHeightPx), mKernel(kernel), mScratch(rasterWidthPx) {}

WarpResult QuadraticWarp::doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                                 FieldRows out) noexcept {
  const OutputGeometry g = OutputGeometry::of(frame, rasterWidthPx(), rasterHeightPx());
  mFit = fitFieldQuadratic(frame, fieldPose, g);
  mHaveFit = true;
  std::uint32_t violations = 0;
  if (mFit.fellBack()) {
    violations = resampleHomography(pixels, mFit.homography, parity, rasterHeightPx(), out, mScratch);
  } else if (mKernel == ResampleKernel::Fast) {
    violations = resampleQuadraticFast(pixels, mFit.quadratic, parity, rasterHeightPx(), out, mScratch);
  } else {
    violations = resampleQuadraticReference(pixels, mFit.quadratic, parity, rasterHeightPx(), out);
  }
  return {WarpStatus::Ok, violations, mFit.fellBack(), fallbackReasonOf(mFit.outcome)};
}

std::optional<glm::dvec2> QuadraticWarp::sourcePx(glm::dvec2 rasterPx) const noexcept {
  if (!mHaveFit) return std::nullopt;
  return mFit(rasterPx);
}

}  // namespace fieldcast::warp
