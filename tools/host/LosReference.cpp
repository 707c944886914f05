// Brute-force segment march, the same rule as LineOfSightTest's reference in ig_core: the first
// sample at or below the surface. It overestimates the crossing by less than one step.
#include "LosReference.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace fieldcast::tools {

std::optional<double> referenceSegmentRangeM(const core::TerrainView& view, const glm::dvec3& fromM,
                                             const glm::dvec3& toM, double stepVoxels) {
  const core::TerrainGeometry& g = view.geometry();
  const double lengthM = glm::length(toM - fromM);
  if (!(lengthM > 0.0)) return std::nullopt;
  const glm::dvec3 direction = (toM - fromM) / lengthM;
  const double stepM = stepVoxels * g.spacingM;
  const double x1 = g.originM.x + (g.widthVox - 1) * g.spacingM;
  const double y1 = g.originM.y + (g.heightVox - 1) * g.spacingM;
  const auto steps = static_cast<long>(std::ceil(lengthM / stepM));
  for (long k = 0; k <= steps; ++k) {
    const double t = std::min(static_cast<double>(k) * stepM, lengthM);
    const glm::dvec3 p = fromM + t * direction;
    if (p.x < g.originM.x || p.x > x1 || p.y < g.originM.y || p.y > y1) continue;
    if (p.z <= view.heightAtM(p.x, p.y, 0)) return t;
  }
  return std::nullopt;
}

}  // namespace fieldcast::tools
