#pragma once
// A rendered frame, as ig_core hands it to prp_warp (DESIGN.md §3): an image larger than the
// display window by a margin on every side, the pose and time it was rendered for, and the world
// points seen at the control pixels, which the warp uses to extrapolate to each field's pose.

#include <fieldcast/Image.h>
#include <fieldcast/Intrinsics.h>
#include <fieldcast/Pose.h>
#include <fieldcast/Time.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace fieldcast {

/// What a control pixel saw.
enum class ControlPointKind : std::uint8_t {
  Missing,  ///< nothing usable (not rendered, or outside the terrain); ignored by the fit
  Surface,  ///< `world` is the 3D point hit, world metres
  Sky,      ///< `world` is the unit world direction of the ray (a point at infinity)
};

/// A control point: a fixed pixel of the frame and what the renderer saw through it.
struct ControlPoint {
  glm::dvec2 framePx{0.0, 0.0};     ///< continuous frame pixel coordinates (margin included)
  glm::dvec3 world{0.0, 0.0, 0.0};  ///< hit point (metres) or sky direction (unit), see kind
  ControlPointKind kind = ControlPointKind::Missing;
};

/// Margin in pixels on each side of the display window inside the frame.
struct MarginPx {
  int x = 0;  ///< columns added on the left and on the right
  int y = 0;  ///< rows added at the top and at the bottom
  friend bool operator==(const MarginPx&, const MarginPx&) = default;
};

/// Rows [first, end) of one frame column.
struct RowRun {
  int first = 0;
  int end = 0;
};

/// The part of a frame a rolled display samples. The IG renders without roll and the warp turns
/// the frame (DESIGN.md §3), so the frame is the bounding box of the turned display window and
/// its margins; near half of that box lies outside the turned window at a steep bank, and is never
/// shown. A frame renders only its footprint — the display window grown by the margins on every
/// side, turned by the roll, within the frame — and repeats each column's end pixels above and
/// below it; a sample outside it is a margin violation. The default is the whole frame; rows() and
/// contains() need the frame's size (widthPx, heightPx), which layoutFrame sets.
struct FrameFootprint {
  bool whole = true;  ///< every pixel of the frame (a level frame, or one not rendered here)
  double cosRoll = 1.0, sinRoll = 0.0;
  double cxPx = 0.0, cyPx = 0.0, fxPx = 1.0, fyPx = 1.0;  ///< the frame's principal point and focal lengths
  /// The grown display window, in the display's normalised coordinates ((u − cx) / fx, (v − cy) / fy)
  double xMin = 0.0, xMax = 0.0, yMin = 0.0, yMax = 0.0;
  int widthPx = 0, heightPx = 0;  ///< the frame's size

  /// Whether continuous frame pixel `px` (pixel centres at +0.5, as the warp samples) lies in the
  /// footprint (false for NaN).
  bool contains(glm::dvec2 px) const noexcept;
  /// The rows column `u` renders: every row a bilinear sample at a point of the footprint reads
  /// from this column. Never empty: a column the footprint misses gets the rows beside its nearest
  /// corner, so it has pixels to repeat.
  RowRun rows(int u) const noexcept;
};

/// One rendered frame. The display window occupies frame pixels
/// [margin.x, margin.x + displayWidth) × [margin.y, margin.y + displayHeight).
struct Frame {
  Image image;  ///< frame pixels, Rgb8 or Grey8, margins included
  /// `image` through the interlace flicker filter, made once by the frame's producer for a field
  /// warper that filters (it then samples this instead of filtering on the field thread). Its
  /// buffer is kept when a frame is recycled; what it holds counts only with hasFlickerFiltered.
  Image flickerFiltered;
  /// flickerFiltered was made from this `image` (warp::makeFlickerFiltered). Whatever changes
  /// `image` afterwards, or reuses the frame for another picture, must clear it.
  bool hasFlickerFiltered = false;
  std::vector<float> rangeM;  ///< per-pixel range along the ray (metres, +inf = sky); empty when not rendered
  Pose pose;                  ///< the pose the frame was rendered for (the IG renders without roll)
  TimePoint poseTime{};       ///< the instant that pose belongs to
  TimePoint renderStart{};    ///< when rendering started
  TimePoint renderEnd{};      ///< when the frame became complete
  Intrinsics intrinsics;      ///< of the whole frame, margins included
  MarginPx margin;
  FrameFootprint footprint;  ///< the pixels rendered; outside it each column repeats its end pixels
  std::uint64_t frameNumber = 0;
  std::vector<ControlPoint> controlPoints;

  int displayWidthPx() const noexcept { return intrinsics.widthPx - 2 * margin.x; }
  int displayHeightPx() const noexcept { return intrinsics.heightPx - 2 * margin.y; }
  bool hasRange() const noexcept { return !rangeM.empty(); }
};

/// The default control pixels: a `perSide` × `perSide` grid spread evenly over the display
/// window of a frame, from `insetFraction` of the window's size in from each edge to the other.
/// Frame pixel coordinates (margin included). The default 3×3 grid gives the nine points of
/// DESIGN.md §3.
std::vector<glm::dvec2> controlGridFramePx(int displayWidthPx, int displayHeightPx, MarginPx margin, int perSide = 3,
                                           double insetFraction = 0.05);

}  // namespace fieldcast
