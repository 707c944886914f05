// Rotation-only reprojection (asynchronous timewarp in VR): the frame's image turned to the
// field's attitude as if every point were at infinity. Exact for the sky and for a camera that
// only rotated; it ignores the parallax of translation, which is what the other warps add.
#include <prp_warp/Warps.h>

namespace fieldcast::warp {

RotationWarp::RotationWarp(int rasterWidthPx, int rasterHeightPx)
    : Warp(rasterWidthPx, rasterHeightPx), mScratch(rasterWidthPx) {}

WarpResult RotationWarp::doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                                FieldRows out) noexcept {
  const OutputGeometry g = OutputGeometry::of(frame, rasterWidthPx(), rasterHeightPx());
  mMap = rotationHomography(frame, fieldPose, g);
  return {WarpStatus::Ok, resampleHomography(pixels, *mMap, parity, rasterHeightPx(), out, mScratch), false};
}

std::optional<glm::dvec2> RotationWarp::sourcePx(glm::dvec2 rasterPx) const noexcept {
  if (!mMap) return std::nullopt;
  return (*mMap)(rasterPx);
}

}  // namespace fieldcast::warp
