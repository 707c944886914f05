// Frame hold: the baseline every other warp must beat. Only the raster scaling is applied.
#include <prp_warp/Warps.h>

namespace fieldcast::warp {

HoldWarp::HoldWarp(int rasterWidthPx, int rasterHeightPx)
    : Warp(rasterWidthPx, rasterHeightPx), mScratch(rasterWidthPx) {}

WarpResult HoldWarp::doWarp(const Frame& frame, const Image& pixels, const Pose& /*fieldPose*/, FieldParity parity,
                            FieldRows out) noexcept {
  const OutputGeometry g = OutputGeometry::of(frame, rasterWidthPx(), rasterHeightPx());
  mLastMap = QuadraticMap::affine(g.offsetPx, g.scale);
  return {WarpStatus::Ok, resampleQuadraticFast(pixels, *mLastMap, parity, rasterHeightPx(), out, mScratch), false};
}

std::optional<glm::dvec2> HoldWarp::sourcePx(glm::dvec2 rasterPx) const noexcept {
  if (!mLastMap) return std::nullopt;
  return (*mLastMap)(rasterPx);
}

}  // namespace fieldcast::warp
