#pragma once
// Pinhole camera intrinsics in pixel units, image convention of DESIGN.md §6: origin at the
// top-left corner of the image, u right, v down, pixel (i, j) has its centre at (i + ½, j + ½).

#include <cmath>
#include <numbers>

namespace fieldcast {

/// A frustum's half-angles from the view axis to the window's edges, radians: left and bottom
/// negative when the axis passes inside the window (CIGI View Definition's convention).
struct FrustumAngles {
  double leftRad = 0.0;
  double rightRad = 0.0;
  double topRad = 0.0;
  double bottomRad = 0.0;

  /// Whether this is a window the renderer and the warps draw: left of right and below top, each
  /// edge under 80° from the view axis on either side (a window may lie wholly off the axis, as
  /// the side screens of a flat wall do). False when an angle is not a number.
  bool renderable() const noexcept {
    constexpr double kMaxRad = 80.0 * std::numbers::pi / 180.0;
    const auto within = [](double a) { return a > -kMaxRad && a < kMaxRad; };
    return leftRad < rightRad && bottomRad < topRad && within(leftRad) && within(rightRad) && within(topRad) &&
           within(bottomRad);
  }
};

/// Pinhole intrinsics of an image `widthPx` × `heightPx`.
/// fx, fy are focal lengths in pixels (fy = fx for square pixels; NTSC's 10:11 pixels differ);
/// (cx, cy) is the principal point in the same continuous pixel coordinates.
struct Intrinsics {
  int widthPx = 0;
  int heightPx = 0;
  double fxPx = 1.0;
  double fyPx = 1.0;
  double cxPx = 0.0;
  double cyPx = 0.0;

  /// A centred camera with the given horizontal field of view (radians) and pixel aspect
  /// (pixel width / pixel height; 1 for square pixels).
  static Intrinsics fromHorizontalFov(int widthPx, int heightPx, double hfovRad, double pixelAspect = 1.0) noexcept {
    Intrinsics k;
    k.widthPx = widthPx;
    k.heightPx = heightPx;
    k.fxPx = 0.5 * widthPx / std::tan(0.5 * hfovRad);
    k.fyPx = k.fxPx * pixelAspect;
    k.cxPx = 0.5 * widthPx;
    k.cyPx = 0.5 * heightPx;
    return k;
  }

  /// The camera whose `widthPx` × `heightPx` window spans `angles` (asymmetric when the view axis
  /// is off the window's centre; the pixels are square only when the angles make them so).
  static Intrinsics fromFrustum(int widthPx, int heightPx, const FrustumAngles& angles) noexcept {
    const double left = std::tan(angles.leftRad), right = std::tan(angles.rightRad);
    const double top = std::tan(angles.topRad), bottom = std::tan(angles.bottomRad);
    Intrinsics k;
    k.widthPx = widthPx;
    k.heightPx = heightPx;
    k.fxPx = widthPx / (right - left);  // u = cx + fx·x: 0 at the left edge, width at the right
    k.cxPx = -left * k.fxPx;
    k.fyPx = heightPx / (top - bottom);  // v = cy − fy·y (v down): 0 at the top edge
    k.cyPx = top * k.fyPx;
    return k;
  }

  /// The half-angles of this camera's window (fromFrustum's inverse).
  FrustumAngles frustum() const noexcept {
    return FrustumAngles{std::atan(-cxPx / fxPx), std::atan((widthPx - cxPx) / fxPx), std::atan(cyPx / fyPx),
                         std::atan((cyPx - heightPx) / fyPx)};
  }

  /// The same camera with `marginXPx`/`marginYPx` more pixels on each side: same focal length,
  /// principal point shifted so the original image sits inside at offset (marginX, marginY).
  Intrinsics withMargin(int marginXPx, int marginYPx) const noexcept {
    Intrinsics k = *this;
    k.widthPx += 2 * marginXPx;
    k.heightPx += 2 * marginYPx;
    k.cxPx += marginXPx;
    k.cyPx += marginYPx;
    return k;
  }

  /// Horizontal field of view in radians (for a centred principal point).
  double horizontalFovRad() const noexcept { return 2.0 * std::atan(0.5 * widthPx / fxPx); }
  /// Vertical field of view in radians (for a centred principal point).
  double verticalFovRad() const noexcept { return 2.0 * std::atan(0.5 * heightPx / fyPx); }

  friend bool operator==(const Intrinsics&, const Intrinsics&) = default;
};

}  // namespace fieldcast
