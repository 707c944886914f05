#include <fieldcast/Conventions.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace fieldcast {

CameraAxes cameraAxes(const Pose& pose) noexcept {
  const double sh = std::sin(pose.headingRad), ch = std::cos(pose.headingRad);
  const double sp = std::sin(pose.pitchRad), cp = std::cos(pose.pitchRad);
  const double sr = std::sin(pose.rollRad), cr = std::cos(pose.rollRad);

  // Heading turns clockwise seen from above: forward north → east.
  const glm::dvec3 forwardLevel{sh, ch, 0.0};
  const glm::dvec3 rightLevel{ch, -sh, 0.0};
  const glm::dvec3 worldUp{0.0, 0.0, 1.0};

  // Pitch tilts forward towards up about the right axis.
  const glm::dvec3 forward = cp * forwardLevel + sp * worldUp;
  const glm::dvec3 upPitched = -sp * forwardLevel + cp * worldUp;

  // Roll about forward: right wing goes down, the up axis leans to the right.
  const glm::dvec3 right = cr * rightLevel - sr * upPitched;
  const glm::dvec3 up = sr * rightLevel + cr * upPitched;
  return {right, up, forward};
}

Pose offsetPose(const Pose& ownship, const ViewOffset& offset) noexcept {
  if (offset.isZero()) return ownship;
  const CameraAxes own = cameraAxes(ownship);
  // The offset's axes at zero ownship attitude are world vectors (east, north, up) = camera
  // (right, forward, up); carry them into the ownship's frame.
  const CameraAxes rel = cameraAxes(Pose{{}, offset.headingRad, offset.pitchRad, offset.rollRad});
  const auto toWorld = [&own](const glm::dvec3& v) { return v.x * own.right + v.y * own.forward + v.z * own.up; };
  const glm::dvec3 forward = toWorld(rel.forward);
  const glm::dvec3 right = toWorld(rel.right);

  Pose out;
  out.positionM = ownship.positionM + toWorld(offset.positionM);
  out.headingRad = std::atan2(forward.x, forward.y);
  out.pitchRad = std::asin(std::clamp(forward.z, -1.0, 1.0));
  // Roll: the angle of the right axis below the level right axis, about forward (cameraAxes).
  const double sh = std::sin(out.headingRad), ch = std::cos(out.headingRad);
  const double sp = std::sin(out.pitchRad), cp = std::cos(out.pitchRad);
  const glm::dvec3 rightLevel{ch, -sh, 0.0};
  const glm::dvec3 upPitched{-sp * sh, -sp * ch, cp};
  out.rollRad = std::atan2(-glm::dot(right, upPitched), glm::dot(right, rightLevel));
  return out;
}

glm::dmat3 worldToCameraRotation(const Pose& pose) noexcept {
  const CameraAxes a = cameraAxes(pose);
  // glm is column-major: build the transpose of [r u f] so that rows are the axes.
  return glm::transpose(glm::dmat3(a.right, a.up, a.forward));
}

glm::dvec3 directionToCamera(const Pose& pose, const glm::dvec3& directionWorld) noexcept {
  const CameraAxes a = cameraAxes(pose);
  return {glm::dot(directionWorld, a.right), glm::dot(directionWorld, a.up), glm::dot(directionWorld, a.forward)};
}

glm::dvec3 worldToCamera(const Pose& pose, const glm::dvec3& pointM) noexcept {
  return directionToCamera(pose, pointM - pose.positionM);
}

std::optional<glm::dvec2> cameraToPixel(const Intrinsics& k, const glm::dvec3& c, double minDepth) noexcept {
  if (!(c.z > minDepth)) return std::nullopt;
  return glm::dvec2{k.cxPx + k.fxPx * c.x / c.z, k.cyPx - k.fyPx * c.y / c.z};
}

std::optional<glm::dvec2> projectPoint(const Pose& pose, const Intrinsics& k, const glm::dvec3& pointM) noexcept {
  return cameraToPixel(k, worldToCamera(pose, pointM));
}

std::optional<glm::dvec2> projectDirection(const Pose& pose, const Intrinsics& k,
                                           const glm::dvec3& directionWorld) noexcept {
  return cameraToPixel(k, directionToCamera(pose, directionWorld));
}

glm::dvec3 pixelRayCamera(const Intrinsics& k, const glm::dvec2& pixel) noexcept {
  return {(pixel.x - k.cxPx) / k.fxPx, -(pixel.y - k.cyPx) / k.fyPx, 1.0};
}

glm::dvec3 pixelRay(const Pose& pose, const Intrinsics& k, const glm::dvec2& pixel) noexcept {
  const glm::dvec3 c = pixelRayCamera(k, pixel);
  const CameraAxes a = cameraAxes(pose);
  return glm::normalize(c.x * a.right + c.y * a.up + c.z * a.forward);
}

}  // namespace fieldcast
