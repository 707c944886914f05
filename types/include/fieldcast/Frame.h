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
