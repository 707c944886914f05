#pragma once
// The geometry both renderers share: the (unrolled) camera's rays in world space, the grid
// transform, and the level-of-detail rule. Keeping it in one place means the fast caster and the
// reference renderer see exactly the same multiresolution surface.

#include <ig_core/RenderSettings.h>
#include <ig_core/TerrainView.h>

#include <fieldcast/Conventions.h>
#include <fieldcast/Intrinsics.h>
#include <fieldcast/Pose.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace fieldcast::core {

/// The view of one frame over one terrain. Immutable after construction; RT-safe to query.
class ViewGeometry {
 public:
  /// `pose.rollRad` is ignored (the IG renders without roll). `quality` as in RenderSettings.
  ViewGeometry(const Pose& pose, const Intrinsics& frame, const TerrainGeometry& terrain, double quality) noexcept;
  /// The same with the grazing-angle rule of `settings` (maxAnisotropy, maxLodStretch).
  ViewGeometry(const Pose& pose, const Intrinsics& frame, const TerrainGeometry& terrain,
               const RenderSettings& settings) noexcept;

  const Pose& pose() const noexcept { return mPose; }  ///< the pose with roll = 0
  const Intrinsics& intrinsics() const noexcept { return mK; }
  const CameraAxes& axes() const noexcept { return mAxes; }

  /// World direction through continuous frame pixel (u, v), scaled so its forward (depth)
  /// component is 1: the point at depth t metres is position + t·ray. RT-safe.
  glm::dvec3 ray(double u, double v) const noexcept {
    const double xc = (u - mK.cxPx) / mK.fxPx;
    const double yc = -(v - mK.cyPx) / mK.fyPx;
    return xc * mAxes.right + yc * mAxes.up + mAxes.forward;
  }

  /// Depth (metres along the forward axis) at which level 0 stops being fine enough to use:
  /// a level-0 voxel projects to `quality` pixels there.
  double lodDepth0M() const noexcept { return mLodDepth0M; }
  /// Level of detail used at depth `depthM`: the smallest L whose voxel still projects to at
  /// least `quality` pixels, clamped to the pyramid. RT-safe.
  int lodLevel(double depthM) const noexcept;
  /// Whether the grazing-angle rule is on (RenderSettings::maxAnisotropy > 0).
  bool grazingLod() const noexcept { return mMaxAnisotropy > 0.0; }
  /// Level of detail for a hit at depth `depthM` seen along `ray` (as from ray()): lodLevel of the
  /// depth stretched by lodStretch(ray). RT-safe.
  int lodLevel(double depthM, const glm::dvec3& ray) const noexcept { return lodLevel(depthM * lodStretch(ray)); }
  /// Factor (1 ..maxLodStretch) by which the grazing-angle rule enlarges the depth the level is
  /// chosen for, for a ray (any length): 1 / (sin(depression)·maxAnisotropy), clamped; the most
  /// for rays at or above the horizon; 1 when the rule is off. RT-safe.
  double lodStretch(const glm::dvec3& ray) const noexcept {
    if (!grazingLod()) return 1.0;
    const double down = -ray.z * mMaxAnisotropy;  // sin(depression)·A·|ray|
    const double length = std::sqrt(ray.x * ray.x + ray.y * ray.y + ray.z * ray.z);
    return down * mMaxLodStretch > length ? std::max(length / down, 1.0) : mMaxLodStretch;
  }
  /// Weight (0..1) of level `level`+1's colour blended into level `level`'s at depth `depthM`:
  /// 0 over the near half of the level's depth range, rising linearly to 1 where the march
  /// switches to `level`+1. RT-safe.
  double levelBlend(double depthM, int level) const noexcept;

 private:
  Pose mPose;
  Intrinsics mK;
  CameraAxes mAxes;
  double mLodDepth0M;
  int mLevels;
  double mMaxAnisotropy = 0.0;
  double mMaxLodStretch = 1.0;
};

}  // namespace fieldcast::core
