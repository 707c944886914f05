#pragma once
// The plain renderer the tests judge the fast one by: every pixel's ray marched on its own in
// small steps against the bilinear height surface of the level of detail at that depth, the
// crossing refined by bisection. Exact (to 1/8 voxel steps and 1e-6 m) and slow; not for real time.

#include <ig_core/RenderSettings.h>
#include <ig_core/TerrainView.h>
#include <ig_core/ViewGeometry.h>

#include <fieldcast/Frame.h>

#include <glm/vec3.hpp>

#include <cstdint>

namespace fieldcast::core {

/// Per-pixel ray–height-field intersection. Thread-compatible (const methods only).
class ReferenceRenderer {
 public:
  explicit ReferenceRenderer(const TerrainView& view);

  /// What one ray saw.
  struct Hit {
    bool hit = false;
    glm::dvec3 pointM{0.0};  ///< world hit point
    double depthM = 0.0;     ///< forward-axis depth of the hit
    int level = 0;           ///< level of detail of the surface hit
    bool basePlane = false;  ///< the hit is on the base plane beyond the terrain's edge
  };

  /// Casts the ray through continuous frame pixel (u, v), from depth `fromDepthM` on (a start
  /// under the surface is a hit there). Not RT-safe (slow).
  Hit cast(const ViewGeometry& geometry, double u, double v, double fromDepthM = 0.0) const noexcept;

  /// Renders a whole frame (image, range always, control points) as the fast renderer would.
  Frame render(const ViewRequest& request, const RenderSettings& settings) const;

 private:
  const TerrainView& mView;
  double mCeilingM;
  std::uint32_t mBaseColourRgba;
};

}  // namespace fieldcast::core
