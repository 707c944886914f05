#pragma once
// The coordinate conventions of DESIGN.md §6, written once. Every module projects and
// unprojects through these functions; tests/ConventionsTest.cpp pins them with golden values.
//
// World:  x east, y north, z up, metres.
// Pose:   heading ψ clockwise from north, then pitch θ nose-up, then roll φ right-wing-down.
// Camera: axes right r, up u, forward f (f is the viewing direction). At zero attitude
//         r = east, u = up, f = north. Camera coordinates of a point P seen from position C:
//         (xc, yc, zc) = ((P−C)·r, (P−C)·u, (P−C)·f), zc > 0 in front of the camera.
// Image:  u = cx + fx·xc/zc,  v = cy − fy·yc/zc  (v grows downwards).

#include <fieldcast/Intrinsics.h>
#include <fieldcast/Pose.h>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <optional>

namespace fieldcast {

/// The camera's orthonormal axes in world coordinates for a pose.
struct CameraAxes {
  glm::dvec3 right;
  glm::dvec3 up;
  glm::dvec3 forward;
};

/// Axes of the camera for heading, pitch, roll (applied in that order). RT-safe.
CameraAxes cameraAxes(const Pose& pose) noexcept;

/// A view's eye relative to the ownship (a display channel's view offset): a position in the
/// ownship's camera axes (x right, y forward, z up, metres), then heading, pitch and roll applied
/// after the ownship's, in the ownship's frame.
struct ViewOffset {
  glm::dvec3 positionM{0.0, 0.0, 0.0};
  double headingRad = 0.0;
  double pitchRad = 0.0;
  double rollRad = 0.0;
  /// True when the offset moves nothing.
  bool isZero() const noexcept {
    return positionM == glm::dvec3(0.0) && headingRad == 0.0 && pitchRad == 0.0 && rollRad == 0.0;
  }
};

/// The pose of the view `offset` from `ownship`; a zero offset returns `ownship` unchanged (to
/// the bit). Pitch is kept within ±90° and heading within (−π, π]. RT-safe.
Pose offsetPose(const Pose& ownship, const ViewOffset& offset) noexcept;

/// World → camera rotation: rows are right, up, forward, so (xc, yc, zc) = R·(P − C). RT-safe.
glm::dmat3 worldToCameraRotation(const Pose& pose) noexcept;

/// Camera coordinates (xc right, yc up, zc forward/depth) of world point `pointM`. RT-safe.
glm::dvec3 worldToCamera(const Pose& pose, const glm::dvec3& pointM) noexcept;

/// Camera coordinates of a world direction (a point at infinity, such as a sky control point). RT-safe.
glm::dvec3 directionToCamera(const Pose& pose, const glm::dvec3& directionWorld) noexcept;

/// Pixel of a point in camera coordinates, or nothing when it is not in front (zc ≤ `minDepth`). RT-safe.
std::optional<glm::dvec2> cameraToPixel(const Intrinsics& k, const glm::dvec3& cameraPoint,
                                        double minDepth = 1e-9) noexcept;

/// Pixel (continuous image coordinates) where world point `pointM` projects; nothing when it
/// is behind the camera. The pixel may lie outside the image. RT-safe.
std::optional<glm::dvec2> projectPoint(const Pose& pose, const Intrinsics& k, const glm::dvec3& pointM) noexcept;

/// Pixel where a world direction (point at infinity) projects; nothing when it points backwards. RT-safe.
std::optional<glm::dvec2> projectDirection(const Pose& pose, const Intrinsics& k,
                                           const glm::dvec3& directionWorld) noexcept;

/// Unit world direction of the ray through continuous pixel `pixel` (u right, v down). RT-safe.
glm::dvec3 pixelRay(const Pose& pose, const Intrinsics& k, const glm::dvec2& pixel) noexcept;

/// Ray in camera coordinates (not normalised, zc = 1) through `pixel`. RT-safe.
glm::dvec3 pixelRayCamera(const Intrinsics& k, const glm::dvec2& pixel) noexcept;

/// Centre of integer pixel (i, j): (i + ½, j + ½). RT-safe.
constexpr glm::dvec2 pixelCentre(int i, int j) noexcept { return {i + 0.5, j + 0.5}; }

}  // namespace fieldcast
