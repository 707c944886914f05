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
  WarpResult r = doWarp(frame, pixels, fieldPose, parity, out);
  // A rolled frame rendered only its footprint (FrameFootprint); the samplers count what fell
  // outside the frame, this what fell outside the footprint (which lies within the frame)
  if (r.status == WarpStatus::Ok && !frame.footprint.whole) {
    r.marginViolations = countOutsideFootprint(frame.footprint, parity, out.heightPx());
  }
  return r;
}

std::uint32_t Warp::countOutsideFootprint(const FrameFootprint& footprint, FieldParity parity,
                                          int rows) const noexcept {
  const int w = mRasterWidthPx;
  std::uint32_t outside = 0;
  for (int r = 0; r < rows; ++r) {
    const double y = rasterRow(parity, r) + 0.5;
    const auto inside = [&](int i) {
      const std::optional<glm::dvec2> p = sourcePx({i + 0.5, y});
      return !p || footprint.contains(*p);  // no sample: nothing read outside
    };
    const bool left = inside(0), right = inside(w - 1);
    if (left && right) continue;
    // A pixel of the row inside, if any: the middle, or the first of a 16-pixel comb
    int in = inside(w / 2) ? w / 2 : -1;
    for (int i = 8; i < w && in < 0; i += 16) {
      if (inside(i)) in = i;
    }
    if (in < 0) {
      outside += static_cast<std::uint32_t>(w);
      continue;
    }
    // The first and last pixels inside, by bisection from `in`
    int first = in, last = in;
    if (!left) {
      int lo = 0;  // outside
      while (first - lo > 1) {
        const int mid = lo + (first - lo) / 2;
        (inside(mid) ? first : lo) = mid;
      }
    } else {
      first = 0;
    }
    if (!right) {
      int hi = w - 1;  // outside
      while (hi - last > 1) {
        const int mid = last + (hi - last) / 2;
        (inside(mid) ? last : hi) = mid;
      }
    } else {
      last = w - 1;
    }
    outside += static_cast<std::uint32_t>(w - (last - first + 1));
  }
  return outside;
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
