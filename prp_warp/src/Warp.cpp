// Input validation shared by every warp, and the factory.
#include <prp_warp/Warp.h>
#include <prp_warp/Warps.h>

#include <cstdlib>
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
    // The boundary between an inside pixel `in` and an outside one `out`: the last inside
    const auto lastInside = [&](int in, int out) {
      while (std::abs(out - in) > 1) {
        const int mid = in + (out - in) / 2;
        (inside(mid) ? in : out) = mid;
      }
      return in;
    };
    const bool left = inside(0), right = inside(w - 1), middle = inside(w / 2);
    if (left && right) {
      // A row bends too little to leave the convex footprint between three points inside it; a
      // row leaving it between its ends (a turned footprint's corner) leaves it around its middle
      if (!middle) outside += static_cast<std::uint32_t>(lastInside(w - 1, w / 2) - lastInside(0, w / 2) - 1);
      continue;
    }
    // A pixel of the row inside, if any: an end, the middle, or the first of a 16-pixel comb
    int in = left ? 0 : right ? w - 1 : middle ? w / 2 : -1;
    for (int i = 8; i < w && in < 0; i += 16) {
      if (inside(i)) in = i;
    }
    if (in < 0) {
      outside += static_cast<std::uint32_t>(w);
      continue;
    }
    // The first and last pixels inside, by bisection from `in` toward an end outside
    const int first = left ? 0 : lastInside(in, 0);
    const int last = right ? w - 1 : lastInside(in, w - 1);
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
