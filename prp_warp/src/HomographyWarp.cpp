// Perspective homography through the control points: exact for a flat scene or a pure rotation,
// a compromise where the control points lie at very different depths.
#include <prp_warp/Warps.h>

namespace fieldcast::warp {

HomographyWarp::HomographyWarp(int rasterWidthPx, int rasterHeightPx)
    : Warp(rasterWidthPx, rasterHeightPx), mScratch(rasterWidthPx) {}

WarpResult HomographyWarp::doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                                  FieldRows out) noexcept {
  const OutputGeometry g = OutputGeometry::of(frame, rasterWidthPx(), rasterHeightPx());
  const Correspondences c = projectControlPoints(frame, fieldPose, g);
  const auto n = static_cast<std::size_t>(c.count);
  FallbackReason reason = FallbackReason::None;
  if (auto h = fitHomography(std::span(c.rasterPx).first(n), std::span(c.framePx).first(n))) {
    mMap = *h;
  } else {
    mMap = rotationHomography(frame, fieldPose, g);
    reason = n < 4 ? FallbackReason::FewPoints : FallbackReason::Degenerate;
  }
  mHaveMap = true;
  return {WarpStatus::Ok, resampleHomography(pixels, mMap, parity, rasterHeightPx(), out, mScratch),
          reason != FallbackReason::None, reason};
}

std::optional<glm::dvec2> HomographyWarp::sourcePx(glm::dvec2 rasterPx) const noexcept {
  if (!mHaveMap) return std::nullopt;
  return mMap(rasterPx);
}

}  // namespace fieldcast::warp
