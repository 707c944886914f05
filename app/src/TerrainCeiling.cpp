#include "TerrainCeiling.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace fieldcast::app {

double terrainCeilingM(const core::TerrainView& view, int level, double xM, double yM) noexcept {
  const core::TerrainGeometry& g = view.geometry();
  // Continuous index of the level's voxel centres, as TerrainView::heightAtM.
  const double cell = g.spacingM * static_cast<double>(1 << level);
  const double half = 0.5 * static_cast<double>((1 << level) - 1) * g.spacingM;
  const double fi = (xM - g.originM.x - half) / cell;
  const double fj = (yM - g.originM.y - half) / cell;
  const double i0 = std::floor(fi);
  const double j0 = std::floor(fj);
  const double tx = std::clamp(fi - i0, 0.0, 1.0);
  const double ty = std::clamp(fj - j0, 0.0, 1.0);
  const int i = static_cast<int>(std::clamp(i0, -2.0, 1e9));
  const int j = static_cast<int>(std::clamp(j0, -2.0, 1e9));
  // The max mip over the 4 × 4 voxels around the cell, then each corner's 3 × 3 maximum.
  std::uint16_t m[4][4];
  for (int b = 0; b < 4; ++b) {
    for (int a = 0; a < 4; ++a) m[b][a] = view.maxHeightQ(level, i - 1 + a, j - 1 + b);
  }
  auto corner = [&m](int a, int b) {
    std::uint16_t best = 0;
    for (int db = 0; db < 3; ++db) {
      for (int da = 0; da < 3; ++da) best = std::max(best, m[b + db][a + da]);
    }
    return static_cast<double>(best);
  };
  const double q =
      (corner(0, 0) * (1 - tx) + corner(1, 0) * tx) * (1 - ty) + (corner(0, 1) * (1 - tx) + corner(1, 1) * tx) * ty;
  return g.heightBaseM + g.heightStepM * q;
}

}  // namespace fieldcast::app
