#pragma once
// What the ray caster is asked to do: quality knob, outputs, sky and haze, frame margins.

#include <ig_core/Entities.h>
#include <ig_core/PrefetchLod.h>

#include <fieldcast/Frame.h>
#include <fieldcast/Intrinsics.h>
#include <fieldcast/Pose.h>
#include <fieldcast/Time.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace fieldcast::core {

/// Colour of the rendered image.
enum class FrameColour : std::uint8_t {
  Rgb,   ///< PixelFormat::Rgb8
  Grey,  ///< PixelFormat::Grey8, BT.601 luma of the colour
};

/// A direction towards the sun: azimuth clockwise from grid north (world +y), elevation above the
/// horizon, degrees.
struct SunDirection {
  double azimuthDeg = 315.0;
  double elevationDeg = 40.0;
  bool operator==(const SunDirection&) const = default;
};

/// Settings of the renderer. Plain values; changing them between frames is cheap.
struct RenderSettings {
  /// Pixel-to-voxel ratio: a level-L voxel is used while it projects to at least `quality` pixels,
  /// then the march switches to level L+1. 1 = the paper's rule; 2 = one level coarser (faster,
  /// blurrier); 0.5 = one level finer. LOD bias = log2(quality).
  double quality = 1.0;
  /// Grazing-angle level of detail. A pixel's footprint on the ground is longer along the ray than
  /// across it, by about 1/sin(depression) for level ground. Where that elongation exceeds
  /// `maxAnisotropy`, the level is chosen for a depth that many times larger (up to
  /// `maxLodStretch`), so the march does not take several grid lines per pixel row. 0 = depth
  /// alone (the seed paper's rule).
  double maxAnisotropy = 0.0;
  double maxLodStretch = 4.0;  ///< at most this factor (2 levels) coarser than depth alone
  bool blendLevels = true;     ///< blend colours of adjacent levels by distance (no LOD seam)
  /// March neighbouring columns in step, eight at a time (the caster's lane march; see ig_core's
  /// RENDERER.md). Off: each column marches on its own, the columns of a staging block in depth
  /// bands.
  bool laneMarch = false;
  int verticalSupersample = 1;  ///< sub-rays per pixel along the column, 1..4 (for shallow pitch)
  FrameColour colourMode = FrameColour::Rgb;
  bool rangeImage = false;                  ///< also produce per-pixel range (metres, +inf = sky)
  glm::dvec3 skyZenithRgb{62, 104, 178};    ///< sky colour straight up, sRGB 0..255
  glm::dvec3 skyHorizonRgb{196, 210, 226};  ///< sky colour at the horizon and haze colour, sRGB 0..255
  double hazeRangeM = 12000.0;              ///< range (m) where haze covers 63% of the terrain; 0 = none
  /// The sun the frame is lit by (a host's time of day). While it is colourSun the terrain's
  /// colours are drawn as stored; otherwise each is scaled by the light its surface gets now over
  /// the light it was baked with (TerrainLight.h), and sky, haze, sticks and entities follow.
  SunDirection sun;
  /// The sun the terrain's colours were baked with, and the share of their light that is
  /// hillshade: the procedural colours' defaults (ProceduralColourOptions). An orthophoto's
  /// colours are taken to be lit the same way.
  SunDirection colourSun;
  double colourHillshade = 0.7;
  double marginFraction = 0.10;  ///< frame margin on each side, fraction of each display dimension
  int controlPointsPerSide = 3;  ///< control points: a perSide × perSide grid over the display
};

/// The levels of detail frames rendered with `settings` draw, for TileCache::prefetch.
inline PrefetchLod prefetchLod(const RenderSettings& settings) noexcept {
  return {settings.quality, settings.maxAnisotropy > 0.0 ? settings.maxLodStretch : 1.0};
}

/// The frame the IG renders for a display window: same focal length, larger by the margin, and
/// grown so that it also covers the display window rotated by the roll (the warp applies roll).
struct FrameLayout {
  Intrinsics frame;          ///< intrinsics of the whole frame (margins included)
  MarginPx margin;           ///< display window offset inside the frame
  FrameFootprint footprint;  ///< the pixels the rolled display samples (footprintOf)
};

/// Frame layout for a display window, a margin fraction (of each display dimension, per side) and
/// a roll angle (radians). Pure function, RT-safe.
FrameLayout layoutFrame(const Intrinsics& display, double marginFraction, double rollRad) noexcept;

/// The control pixels (DESIGN.md §3) of a frame laid out for `display` at `rollRad`: a `perSide` ×
/// `perSide` grid over the display window as the warp turns it into the frame (controlGridFramePx's
/// grid, turned by the roll about the principal point). Over the shown part of the frame, so the
/// warp's fit interpolates the field rather than extrapolating it into a rolled field's corners.
/// Allocates the returned grid.
std::vector<glm::dvec2> controlPixelsOf(const Intrinsics& display, const FrameLayout& layout, double rollRad,
                                        int perSide);

/// The footprint (FrameFootprint) of frame `frame` laid out for `display` at `rollRad`: the
/// display window grown by the margins of a level frame, in whole pixels, turned by the roll.
/// Whole for a level frame. Pure function, RT-safe.
FrameFootprint footprintOf(const Intrinsics& display, const Intrinsics& frame, double marginFraction,
                           double rollRad) noexcept;

}  // namespace fieldcast::core

namespace fieldcast::core {

/// One frame to render: the pose it is for, when that pose holds, and the display window.
struct ViewRequest {
  Pose pose;                             ///< camera pose; roll only sizes the frame (the IG renders unrolled)
  TimePoint poseTime{};                  ///< the instant the pose belongs to (copied into the Frame)
  Intrinsics display;                    ///< intrinsics of the display window (without margin)
  std::uint64_t frameNumber = 0;         ///< copied into the Frame
  std::vector<EntityInstance> entities;  ///< moving entities at `poseTime` (Entities.h)
};

}  // namespace fieldcast::core
