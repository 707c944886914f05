// Camera rays, frame layout with margins and roll, and the level-of-detail rule.
#include <ig_core/RenderSettings.h>
#include <ig_core/ViewGeometry.h>

#include <algorithm>
#include <cmath>

namespace fieldcast::core {

FrameLayout layoutFrame(const Intrinsics& display, double marginFraction, double rollRad) noexcept {
  // Corners of the display window in normalised camera coordinates, rotated by the roll the warp
  // will apply, mapped back to pixels: the unrolled frame must contain all four.
  const double c = std::cos(rollRad);
  const double s = std::sin(rollRad);
  double needLeft = display.cxPx, needRight = display.widthPx - display.cxPx;
  double needTop = display.cyPx, needBottom = display.heightPx - display.cyPx;
  for (const double u : {0.0, static_cast<double>(display.widthPx)}) {
    for (const double v : {0.0, static_cast<double>(display.heightPx)}) {
      const double x = (u - display.cxPx) / display.fxPx;
      const double y = (v - display.cyPx) / display.fyPx;
      const double du = (c * x - s * y) * display.fxPx;
      const double dv = (s * x + c * y) * display.fyPx;
      needLeft = std::max(needLeft, -du);
      needRight = std::max(needRight, du);
      needTop = std::max(needTop, -dv);
      needBottom = std::max(needBottom, dv);
    }
  }
  const double growX = std::max(needLeft - display.cxPx, needRight - (display.widthPx - display.cxPx));
  const double growY = std::max(needTop - display.cyPx, needBottom - (display.heightPx - display.cyPx));
  const double fraction = std::max(marginFraction, 0.0);
  MarginPx margin;
  margin.x = static_cast<int>(std::ceil(growX + fraction * display.widthPx - 1e-9));
  margin.y = static_cast<int>(std::ceil(growY + fraction * display.heightPx - 1e-9));
  const Intrinsics frame = display.withMargin(margin.x, margin.y);
  return FrameLayout{frame, margin, footprintOf(display, frame, fraction, rollRad)};
}

std::vector<glm::dvec2> controlPixelsOf(const Intrinsics& display, const FrameLayout& layout, double rollRad,
                                        int perSide) {
  std::vector<glm::dvec2> pixels = controlGridFramePx(display.widthPx, display.heightPx, layout.margin, perSide);
  if (rollRad == 0.0) return pixels;
  // Display normalised (x, y) lands at frame normalised (c·x − s·y, s·x + c·y), as the footprint's
  const double c = std::cos(rollRad), s = std::sin(rollRad);
  const Intrinsics& frame = layout.frame;
  for (glm::dvec2& px : pixels) {
    const double x = (px.x - frame.cxPx) / frame.fxPx, y = (px.y - frame.cyPx) / frame.fyPx;
    px = {frame.cxPx + (c * x - s * y) * frame.fxPx, frame.cyPx + (s * x + c * y) * frame.fyPx};
  }
  return pixels;
}

FrameFootprint footprintOf(const Intrinsics& display, const Intrinsics& frame, double marginFraction,
                           double rollRad) noexcept {
  // The display window grown by the margins a level frame would have, in whole pixels
  const double fraction = std::max(marginFraction, 0.0);
  const double growX = std::ceil(fraction * display.widthPx - 1e-9);
  const double growY = std::ceil(fraction * display.heightPx - 1e-9);
  FrameFootprint f;
  f.whole = false;
  f.cosRoll = std::cos(rollRad);
  f.sinRoll = std::sin(rollRad);
  f.cxPx = frame.cxPx;
  f.cyPx = frame.cyPx;
  f.fxPx = frame.fxPx;
  f.fyPx = frame.fyPx;
  f.xMin = (-display.cxPx - growX) / display.fxPx;
  f.xMax = (display.widthPx - display.cxPx + growX) / display.fxPx;
  f.yMin = (-display.cyPx - growY) / display.fyPx;
  f.yMax = (display.heightPx - display.cyPx + growY) / display.fyPx;
  f.widthPx = frame.widthPx;
  f.heightPx = frame.heightPx;
  // Whole when it holds the frame's corners (a level frame; the tolerance absorbs rounding)
  FrameFootprint grown = f;
  constexpr double kTolerance = 1e-9;
  grown.xMin -= kTolerance;
  grown.xMax += kTolerance;
  grown.yMin -= kTolerance;
  grown.yMax += kTolerance;
  f.whole = grown.contains({0.0, 0.0}) && grown.contains({frame.widthPx, 0.0}) &&
            grown.contains({0.0, frame.heightPx}) && grown.contains({frame.widthPx, frame.heightPx});
  return f;
}

ViewGeometry::ViewGeometry(const Pose& pose, const Intrinsics& frame, const TerrainGeometry& terrain,
                           double quality) noexcept
    : mPose(pose), mK(frame), mLevels(terrain.levels) {
  mPose.rollRad = 0.0;
  mAxes = cameraAxes(mPose);
  mLodDepth0M = terrain.spacingM * frame.fxPx / std::max(quality, 1e-3);
}

ViewGeometry::ViewGeometry(const Pose& pose, const Intrinsics& frame, const TerrainGeometry& terrain,
                           const RenderSettings& settings) noexcept
    : ViewGeometry(pose, frame, terrain, settings.quality) {
  mMaxAnisotropy = std::max(settings.maxAnisotropy, 0.0);
  mMaxLodStretch = std::max(settings.maxLodStretch, 1.0);
}

int ViewGeometry::lodLevel(double depthM) const noexcept {
  if (!(depthM > mLodDepth0M)) return 0;
  int exponent = 0;
  const double mantissa = std::frexp(depthM / mLodDepth0M, &exponent);  // ratio = mantissa · 2^exponent
  const int level = mantissa == 0.5 ? exponent - 1 : exponent;          // ceil(log2(ratio))
  return std::min(level, mLevels - 1);
}

double ViewGeometry::levelBlend(double depthM, int level) const noexcept {
  if (level >= mLevels - 1) return 0.0;
  // Level L covers depths (½, 1]·Z0·2^L; the blend ramps over the far half of that, 0 at ¾ and 1 at
  // the switch: continuous at the switch, and the near half of each level needs no second fetch.
  return std::clamp(4.0 * depthM / (mLodDepth0M * std::ldexp(1.0, level)) - 3.0, 0.0, 1.0);
}

}  // namespace fieldcast::core
