// A channel's eye and window from [view] (ChannelView.h).
#include "ChannelView.h"

#include <cmath>

namespace fieldcast::app {

namespace {

// −1 for the left eye, +1 for the right, 0 for a centre channel.
double eyeSide(Eye eye) noexcept { return eye == Eye::Left ? -1.0 : eye == Eye::Right ? 1.0 : 0.0; }

}  // namespace

ViewOffset eyeOffset(const ViewOffset& head, const ViewConfig& view) noexcept {
  const double side = eyeSide(view.eye);
  if (side == 0.0) return head;
  // The head's right axis in the ownship's axes (x right, y forward, z up): at zero ownship
  // attitude those are the world's east, north and up, the axes cameraAxes gives.
  const glm::dvec3 right = cameraAxes(Pose{{}, head.headingRad, head.pitchRad, head.rollRad}).right;
  ViewOffset eye = head;
  eye.positionM += side * 0.5 * view.eyeSeparationM * right;
  return eye;
}

ChannelView channelViewOf(const ViewConfig& view, int widthPx, int heightPx, double hfovRad) noexcept {
  ChannelView out;
  out.offset = eyeOffset(view.offset, view);
  const double side = eyeSide(view.eye);
  const bool converged = side != 0.0 && std::isfinite(view.convergenceM);
  if (!view.frustum && !converged) {
    out.display = Intrinsics::fromHorizontalFov(widthPx, heightPx, hfovRad);
    return out;
  }
  FrustumAngles angles = view.frustum.value_or(Intrinsics::fromHorizontalFov(widthPx, heightPx, hfovRad).frustum());
  if (converged) {
    // The window moves towards the other eye: seen from the left eye the plane at Zc lies
    // e/2 further right than from the head
    const double shift = -side * 0.5 * view.eyeSeparationM / view.convergenceM;
    angles.leftRad = std::atan(std::tan(angles.leftRad) + shift);
    angles.rightRad = std::atan(std::tan(angles.rightRad) + shift);
  }
  out.display = Intrinsics::fromFrustum(widthPx, heightPx, angles);
  return out;
}

}  // namespace fieldcast::app
