#pragma once
// The parts of a Frame both renderers fill the same way: layout with margins, pose without roll,
// buffers, control pixel positions, and what a control ray saw.
#include <ig_core/RenderSettings.h>

#include <fieldcast/Conventions.h>
#include <fieldcast/Frame.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>
#include <limits>

namespace fieldcast::core {

/// A frame with its layout, pose (roll 0), buffers and control pixels set; pixels not rendered yet.
/// The buffers of `reuse` are recycled (no allocation once frames stop growing).
inline Frame frameShell(const ViewRequest& request, const RenderSettings& settings, bool withRange,
                        Frame&& reuse = Frame{}) {
  const FrameLayout layout = layoutFrame(request.display, settings.marginFraction, request.pose.rollRad);
  Frame frame = std::move(reuse);
  frame.controlPoints.clear();
  frame.intrinsics = layout.frame;
  frame.margin = layout.margin;
  frame.footprint = layout.footprint;
  frame.pose = request.pose;
  frame.pose.rollRad = 0.0;
  frame.poseTime = request.poseTime;
  frame.frameNumber = request.frameNumber;
  frame.image.resize(layout.frame.widthPx, layout.frame.heightPx,
                     settings.colourMode == FrameColour::Grey ? PixelFormat::Grey8 : PixelFormat::Rgb8);
  frame.hasFlickerFiltered = false;  // the copy is the frame before's (its buffer is kept)
  frame.rangeM.clear();
  if (withRange) {
    frame.rangeM.assign(
        static_cast<std::size_t>(layout.frame.widthPx) * static_cast<std::size_t>(layout.frame.heightPx),
        std::numeric_limits<float>::infinity());
  }
  for (const glm::dvec2& px :
       controlPixelsOf(request.display, layout, request.pose.rollRad, std::max(settings.controlPointsPerSide, 2))) {
    frame.controlPoints.push_back(ControlPoint{px, {}, ControlPointKind::Missing});
  }
  return frame;
}

/// Repeats a column's end pixels over its rows outside `run` (FrameFootprint::rows): the rows
/// above get row run.first's pixel and range, the rows below row run.end − 1's. `pixels` (row 0's
/// pixel, `bytesPerPixel` each, `pixelStride` bytes from row to row) and `ranges` (row 0's,
/// `rangeStride` floats apart) may be null. RT-safe.
inline void repeatColumnEnds(std::uint8_t* pixels, std::size_t bytesPerPixel, std::size_t pixelStride, float* ranges,
                             std::size_t rangeStride, int rows, RowRun run) noexcept {
  const auto fill = [&](int from, int to, int source) {
    const auto src = static_cast<std::size_t>(source);
    for (auto v = static_cast<std::size_t>(from); v < static_cast<std::size_t>(to); ++v) {
      if (pixels != nullptr) std::memcpy(pixels + v * pixelStride, pixels + src * pixelStride, bytesPerPixel);
      if (ranges != nullptr) ranges[v * rangeStride] = ranges[src * rangeStride];
    }
  };
  fill(0, run.first, run.first);
  fill(run.end, rows, run.end - 1);
}

/// repeatColumnEnds on column u of `frame` (its image, and its range when it has one).
inline void repeatColumnEnds(Frame& frame, int u, RowRun run) noexcept {
  const std::size_t bpp = rowBytes(frame.image.format(), 1);
  const auto w = static_cast<std::size_t>(frame.intrinsics.widthPx);
  repeatColumnEnds(frame.image.bytes().data() + static_cast<std::size_t>(u) * bpp, bpp, frame.image.strideBytes(),
                   frame.hasRange() ? frame.rangeM.data() + u : nullptr, w, frame.intrinsics.heightPx, run);
}

/// Records what the control ray through `cp.framePx` saw: a surface point, or the sky direction.
inline void setControlPoint(ControlPoint& cp, const Frame& frame, bool hit, const glm::dvec3& pointM) noexcept {
  if (hit) {
    cp.world = pointM;
    cp.kind = ControlPointKind::Surface;
  } else {
    cp.world = pixelRay(frame.pose, frame.intrinsics, cp.framePx);
    cp.kind = ControlPointKind::Sky;
  }
}

}  // namespace fieldcast::core
