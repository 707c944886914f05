// Input validation shared by every warp, and the factory.
#include <prp_warp/Warp.h>
#include <prp_warp/Warps.h>

#include <stdexcept>
#include <string>

namespace fieldcast::warp {

std::optional<WarpKind> warpKindFromString(std::string_view name) noexcept {
  for (WarpKind k : {WarpKind::Hold, WarpKind::Quadratic, WarpKind::Homography, WarpKind::Range3d, WarpKind::Rotation,
                     WarpKind::Mesh}) {
    if (toString(k) == name) return k;
  }
  return std::nullopt;
}

WarpResult Warp::warp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                      FieldRows out) noexcept {
  const Image& img = frame.image;
  const bool frameOk = !img.empty() && img.widthPx() == frame.intrinsics.widthPx &&
                       img.heightPx() == frame.intrinsics.heightPx && frame.displayWidthPx() > 0 &&
                       frame.displayHeightPx() > 0 && pixels.sameShape(img) &&
                       (img.format() == PixelFormat::Grey8 || img.format() == PixelFormat::Rgb8) &&
                       img.widthPx() >= 2 && img.heightPx() >= 2;
  if (!frameOk) return {WarpStatus::BadFrame, 0, false};
  if (out.widthPx() != mRasterWidthPx || !resampleShapesValid(pixels, parity, mRasterHeightPx, out)) {
    return {WarpStatus::BadOutput, 0, false};
  }
  return doWarp(frame, pixels, fieldPose, parity, out);
}

std::unique_ptr<Warp> makeWarp(WarpKind kind, int rasterWidthPx, int rasterHeightPx) {
  if (rasterWidthPx < 2 || rasterHeightPx < 2) {
    throw std::invalid_argument("warp: output raster must be at least 2x2, got " + std::to_string(rasterWidthPx) + "x" +
                                std::to_string(rasterHeightPx));
  }
  switch (kind) {
    case WarpKind::Hold: return std::make_unique<HoldWarp>(rasterWidthPx, rasterHeightPx);
    case WarpKind::Quadratic: return std::make_unique<QuadraticWarp>(rasterWidthPx, rasterHeightPx);
    case WarpKind::Homography: return std::make_unique<HomographyWarp>(rasterWidthPx, rasterHeightPx);
    case WarpKind::Range3d: return std::make_unique<Range3dWarp>(rasterWidthPx, rasterHeightPx);
    case WarpKind::Rotation: return std::make_unique<RotationWarp>(rasterWidthPx, rasterHeightPx);
    case WarpKind::Mesh: return std::make_unique<MeshWarp>(rasterWidthPx, rasterHeightPx);
  }
  throw std::invalid_argument("warp: unknown kind");
}

}  // namespace fieldcast::warp
