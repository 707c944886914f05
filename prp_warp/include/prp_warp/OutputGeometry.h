#pragma once
// How the output raster sits on a frame: the raster covers the frame's display window exactly,
// scaled to the raster's size. Scaling to the output raster is therefore folded into every warp's
// map (one resample per pixel, not two).

#include <fieldcast/Frame.h>
#include <fieldcast/Intrinsics.h>

#include <glm/vec2.hpp>

namespace fieldcast::warp {

/// Geometry of the output raster relative to one frame.
struct OutputGeometry {
  Intrinsics raster;              ///< pinhole intrinsics of the output raster (a camera at the field pose)
  glm::dvec2 offsetPx{0.0, 0.0};  ///< frame pixel of raster pixel (0, 0): the margin
  glm::dvec2 scale{1.0, 1.0};     ///< frame pixels per raster pixel

  /// The raster `widthPx` × `heightPx` over the display window of `frame`. RT-safe.
  static OutputGeometry of(const Frame& frame, int widthPx, int heightPx) noexcept {
    OutputGeometry g;
    g.scale = {static_cast<double>(frame.displayWidthPx()) / widthPx,
               static_cast<double>(frame.displayHeightPx()) / heightPx};
    g.offsetPx = {static_cast<double>(frame.margin.x), static_cast<double>(frame.margin.y)};
    const Intrinsics& k = frame.intrinsics;
    g.raster.widthPx = widthPx;
    g.raster.heightPx = heightPx;
    g.raster.fxPx = k.fxPx / g.scale.x;
    g.raster.fyPx = k.fyPx / g.scale.y;
    g.raster.cxPx = (k.cxPx - g.offsetPx.x) / g.scale.x;
    g.raster.cyPx = (k.cyPx - g.offsetPx.y) / g.scale.y;
    return g;
  }

  /// Frame pixel under raster pixel `rasterPx` with no warp (the hold map). RT-safe.
  glm::dvec2 framePxOf(glm::dvec2 rasterPx) const noexcept { return offsetPx + scale * rasterPx; }
};

}  // namespace fieldcast::warp
