#pragma once
// The parts of a Frame both renderers fill the same way: layout with margins, pose without roll,
// buffers, control pixel positions, and what a control ray saw.
#include <ig_core/RenderSettings.h>

#include <fieldcast/Conventions.h>
#include <fieldcast/Frame.h>

#include <glm/geometric.hpp>

#include <cmath>
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
  for (const glm::dvec2& px : controlGridFramePx(request.display.widthPx, request.display.heightPx, layout.margin,
                                                 std::max(settings.controlPointsPerSide, 2))) {
    frame.controlPoints.push_back(ControlPoint{px, {}, ControlPointKind::Missing});
  }
  return frame;
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
