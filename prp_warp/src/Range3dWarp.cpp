// Post-rendering 3D warping (Mark, McMillan & Bishop, "Post-Rendering 3D Warping", I3D 1997):
// forward-map every frame pixel through its range into the field's camera. Instead of splatting
// colours, each raster pixel near a projected sample records the frame position that maps onto
// its own centre (the sample's frame pixel, corrected by the sub-pixel offset of the
// projection); the frame is then resampled bilinearly through that per-pixel map, so the 3D warp
// keeps the same filtering as the other warps and exposes the same sampling map. The sub-pixel
// correction uses the local Jacobian of the rotation-only homography, exact for any rotation
// between the two poses (roll included) and first-order for the parallax of translation.
#include <prp_warp/Warps.h>

#include <fieldcast/Conventions.h>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fieldcast::warp {
namespace {

constexpr float kNoSample = std::numeric_limits<float>::infinity();
constexpr float kSkyDepth = std::numeric_limits<float>::max();  // loses to every surface, beats "no sample"
constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr double kMinDepth = 1e-6;

bool rowInField(int rasterRowIndex, FieldParity parity) noexcept {
  switch (parity) {
    case FieldParity::Top: return (rasterRowIndex & 1) == 0;
    case FieldParity::Bottom: return (rasterRowIndex & 1) == 1;
    case FieldParity::Progressive: return true;
  }
  return true;
}

}  // namespace

Range3dWarp::Range3dWarp(int rasterWidthPx, int rasterHeightPx)
    : Warp(rasterWidthPx, rasterHeightPx),
      mDepth(static_cast<std::size_t>(rasterWidthPx) * static_cast<std::size_t>(rasterHeightPx), kNoSample),
      mMapX(mDepth.size(), kNan),
      mMapY(mDepth.size(), kNan),
      mFallback(rasterWidthPx, rasterHeightPx) {}

void Range3dWarp::splat(const Frame& frame, const Pose& fieldPose, const OutputGeometry& g,
                        FieldParity parity) noexcept {
  const int rw = rasterWidthPx(), rh = rasterHeightPx();
  const Intrinsics& kf = frame.intrinsics;
  const Intrinsics& ko = g.raster;
  // Frame camera → field camera: p_field = M·p_frame + t.
  const glm::dmat3 rFrame = worldToCameraRotation(frame.pose);
  const glm::dmat3 rField = worldToCameraRotation(fieldPose);
  const glm::dmat3 m = rField * glm::transpose(rFrame);
  const glm::dvec3 t = rField * (frame.pose.positionM - fieldPose.positionM);
  const Homography rotation = rotationHomography(frame, fieldPose, g);

  for (int j = 0; j < kf.heightPx; ++j) {
    const float* range = frame.rangeM.data() + static_cast<std::size_t>(j) * static_cast<std::size_t>(kf.widthPx);
    const double yc = -(j + 0.5 - kf.cyPx) / kf.fyPx;
    for (int i = 0; i < kf.widthPx; ++i) {
      const float r = range[i];
      if (!(r > 0.0f)) continue;  // unrendered or NaN: no sample
      const glm::dvec3 ray{(i + 0.5 - kf.cxPx) / kf.fxPx, yc, 1.0};
      // Lift to 3D along the ray (range is the distance, not the depth); sky moves as a direction
      glm::dvec3 p;
      float depth;
      if (std::isinf(r)) {
        p = m * ray;
        depth = kSkyDepth;
      } else {
        p = m * (ray * (static_cast<double>(r) / std::sqrt(glm::dot(ray, ray)))) + t;
        depth = static_cast<float>(p.z);
      }
      if (!(p.z > kMinDepth)) continue;
      const double u = ko.cxPx + ko.fxPx * p.x / p.z;
      const double v = ko.cyPx - ko.fyPx * p.y / p.z;
      if (!(u > -1.0 && u < rw + 1.0 && v > -1.0 && v < rh + 1.0)) continue;  // off the raster (and no int overflow)
      // The 2 × 2 raster pixels whose centres surround the projection (covers up to 2× zoom)
      const int u0 = static_cast<int>(std::floor(u - 0.5));
      const int v0 = static_cast<int>(std::floor(v - 0.5));
      for (int vy = v0; vy <= v0 + 1; ++vy) {
        if (vy < 0 || vy >= rh || !rowInField(vy, parity)) continue;
        for (int ux = u0; ux <= u0 + 1; ++ux) {
          if (ux < 0 || ux >= rw) continue;
          const std::size_t idx = static_cast<std::size_t>(vy) * static_cast<std::size_t>(rw) + ux;
          if (!(depth < mDepth[idx])) continue;
          mDepth[idx] = depth;
          // Frame position that lands on this raster centre, to first order: the sample's frame
          // pixel moved by the offset from the projection to the centre, carried through the
          // rotation-only homography (which holds the roll and the turn between the two poses)
          const glm::dvec2 offset = rotation(glm::dvec2{ux + 0.5, vy + 0.5}) - rotation(glm::dvec2{u, v});
          const bool offsetOk = std::isfinite(offset.x) && std::isfinite(offset.y);
          mMapX[idx] = static_cast<float>(i + 0.5 + (offsetOk ? offset.x : (ux + 0.5 - u) * g.scale.x));
          mMapY[idx] = static_cast<float>(j + 0.5 + (offsetOk ? offset.y : (vy + 0.5 - v) * g.scale.y));
        }
      }
    }
  }
}

void Range3dWarp::fillHoles(FieldParity parity, const OutputGeometry& g) noexcept {
  const int rw = rasterWidthPx(), rh = rasterHeightPx();
  const int rowStep = parity == FieldParity::Progressive ? 1 : 2;
  int lastFilledRow = -1;
  const int firstRow = parity == FieldParity::Bottom ? 1 : 0;
  for (int y = firstRow; y < rh; y += rowStep) {
    const std::size_t base = static_cast<std::size_t>(y) * static_cast<std::size_t>(rw);
    float* depth = mDepth.data() + base;
    float* mx = mMapX.data() + base;
    float* my = mMapY.data() + base;
    // Fill each run of holes from the farther of its two neighbours (disocclusions reveal the
    // background), continuing that neighbour's map across the gap.
    int x = 0;
    bool any = false;
    while (x < rw) {
      if (depth[x] != kNoSample) {
        any = true;
        ++x;
        continue;
      }
      const int start = x;
      while (x < rw && depth[x] == kNoSample) ++x;
      const int left = start - 1, right = x;  // neighbours, possibly outside the row
      int from = -1;
      if (left >= 0 && right < rw) {
        from = depth[left] >= depth[right] ? left : right;
      } else if (left >= 0) {
        from = left;
      } else if (right < rw) {
        from = right;
      }
      if (from < 0) break;  // the whole row is empty
      for (int k = start; k < x; ++k) {
        mx[k] = mx[from] + static_cast<float>((k - from) * g.scale.x);
        my[k] = my[from];
      }
      // Mark filled pixels with the source depth so later runs see them as background
      for (int k = start; k < x; ++k) depth[k] = depth[from];
    }
    if (!any && lastFilledRow >= 0) {
      // An empty row (strong vertical zoom): continue the nearest filled row above.
      continueRow(lastFilledRow, y, g);
      any = true;
    }
    if (any) {
      // The field's first rows got no splat (it sees above the frame's top): continue the first
      // filled row up to them
      if (lastFilledRow < 0)
        for (int above = firstRow; above < y; above += rowStep) continueRow(y, above, g);
      lastFilledRow = y;
    }
  }
}

void Range3dWarp::continueRow(int filledRow, int emptyRow, const OutputGeometry& g) noexcept {
  const int rw = rasterWidthPx();
  const std::size_t src = static_cast<std::size_t>(filledRow) * static_cast<std::size_t>(rw);
  const std::size_t dst = static_cast<std::size_t>(emptyRow) * static_cast<std::size_t>(rw);
  for (int k = 0; k < rw; ++k) {
    mMapX[dst + k] = mMapX[src + k];
    mMapY[dst + k] = mMapY[src + k] + static_cast<float>((emptyRow - filledRow) * g.scale.y);
    mDepth[dst + k] = mDepth[src + k];
  }
}

WarpResult Range3dWarp::doWarp(const Frame& frame, const Image& pixels, const Pose& fieldPose, FieldParity parity,
                               FieldRows out) noexcept {
  const auto framePixels = static_cast<std::size_t>(frame.intrinsics.widthPx) * frame.intrinsics.heightPx;
  if (!frame.hasRange() || frame.rangeM.size() != framePixels) {
    mUsedFallback = true;
    mLastParity.reset();
    WarpResult r = mFallback.warp(frame, pixels, fieldPose, parity, out);
    r.fellBack = true;
    r.fallbackReason = FallbackReason::NoRange;
    return r;
  }
  mUsedFallback = false;
  const OutputGeometry g = OutputGeometry::of(frame, rasterWidthPx(), rasterHeightPx());
  const int rw = rasterWidthPx();

  // Clear the field's rows, splat, fill
  for (int r = 0; r < out.heightPx(); ++r) {
    const std::size_t base = static_cast<std::size_t>(rasterRow(parity, r)) * static_cast<std::size_t>(rw);
    std::fill_n(mDepth.begin() + static_cast<std::ptrdiff_t>(base), rw, kNoSample);
    std::fill_n(mMapX.begin() + static_cast<std::ptrdiff_t>(base), rw, kNan);
    std::fill_n(mMapY.begin() + static_cast<std::ptrdiff_t>(base), rw, kNan);
  }
  splat(frame, fieldPose, g, parity);
  fillHoles(parity, g);
  mLastParity = parity;

  // Resample through the per-pixel map
  std::uint32_t violations = 0;
  for (int r = 0; r < out.heightPx(); ++r) {
    const std::size_t base = static_cast<std::size_t>(rasterRow(parity, r)) * static_cast<std::size_t>(rw);
    violations += sampleRow(pixels, mMapX.data() + base, mMapY.data() + base, rw, out.begin(0, r));
    out.end(0, rw, r);
  }
  return {WarpStatus::Ok, violations, false};
}

std::optional<glm::dvec2> Range3dWarp::sourcePx(glm::dvec2 rasterPx) const noexcept {
  if (mUsedFallback) return mFallback.sourcePx(rasterPx);
  if (!mLastParity) return std::nullopt;
  if (!(rasterPx.x >= 0.0 && rasterPx.x < rasterWidthPx() && rasterPx.y >= 0.0 && rasterPx.y < rasterHeightPx())) {
    return std::nullopt;
  }
  const int u = static_cast<int>(rasterPx.x);
  const int v = static_cast<int>(rasterPx.y);
  if (!rowInField(v, *mLastParity)) return std::nullopt;
  const std::size_t idx = static_cast<std::size_t>(v) * static_cast<std::size_t>(rasterWidthPx()) + u;
  if (std::isnan(mMapX[idx])) return std::nullopt;
  // The map holds the source of the pixel's centre (the point sampled for the pixel)
  return glm::dvec2{mMapX[idx], mMapY[idx]};
}

}  // namespace fieldcast::warp
