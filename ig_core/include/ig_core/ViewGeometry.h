#pragma once
// The geometry both renderers share: the (unrolled) camera's rays in world space, the grid
// transform, and the level-of-detail rule. Keeping it in one place means the fast caster and the
// reference renderer see exactly the same multiresolution surface.

#include <ig_core/TerrainView.h>

#include <fieldcast/Conventions.h>
#include <fieldcast/Intrinsics.h>
#include <fieldcast/Pose.h>

#include <glm/vec3.hpp>

namespace fieldcast::core {

/// The view of one frame over one terrain. Immutable after construction; RT-safe to query.
class ViewGeometry {
 public:
  /// `pose.rollRad` is ignored (the IG renders without roll). `quality` as in RenderSettings.
  ViewGeometry(const Pose& pose, const Intrinsics& frame, const TerrainGeometry& terrain, double quality) noexcept;

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
};

}  // namespace fieldcast::core
