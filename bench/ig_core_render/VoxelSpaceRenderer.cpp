#include "VoxelSpaceRenderer.h"

#include "ShareRows.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace fieldcast::core {

std::size_t renderVoxelSpace(const LevelZeroGrid& grid, const ViewGeometry& view, int threads,
                             std::vector<std::uint8_t>& rgb) {
  const Intrinsics& k = view.intrinsics();
  const TerrainGeometry& g = grid.geometry;
  rgb.assign(static_cast<std::size_t>(k.widthPx) * static_cast<std::size_t>(k.heightPx) * 3, 0);
  const Pose& pose = view.pose();
  const double camX = (pose.positionM.x - g.originM.x) / g.spacingM;  // in voxels
  const double camY = (pose.positionM.y - g.originM.y) / g.spacingM;
  const double camZ = pose.positionM.z;
  // The heading's ground axes (x east, y north; heading clockwise from north)
  const double fwdX = std::sin(pose.headingRad), fwdY = std::cos(pose.headingRad);
  const double rightX = fwdY, rightY = -fwdX;
  const double horizonRow = k.cyPx + k.fyPx * std::tan(pose.pitchRad);  // the shear
  const double farM = g.spacingM * std::hypot(g.widthVox, g.heightVox);
  std::atomic<std::size_t> shown{0};
  // The columns are the work: shared out in blocks, as rows of the transposed image
  shareRows(k.widthPx, 8, threads, [&](int u0, int u1) {
    std::size_t filled = 0;
    for (int u = u0; u < u1; ++u) {
      const double xc = (u + 0.5 - k.cxPx) / k.fxPx;
      const double dirX = (fwdX + xc * rightX) / g.spacingM, dirY = (fwdY + xc * rightY) / g.spacingM;
      int top = k.heightPx;  // rows at and below this are drawn
      for (double z = g.spacingM; z < farM && top > 0; z += std::max(g.spacingM, z / k.fyPx)) {
        // The nearest voxel (off the grid: the walk is over; checked before the truncation, which
        // rounds toward zero)
        const double x = camX + z * dirX + 0.5, y = camY + z * dirY + 0.5;
        if (!(x >= 0.0 && y >= 0.0)) break;
        const auto i = static_cast<int>(x), j = static_cast<int>(y);
        if (i >= g.widthVox || j >= g.heightVox) break;
        const double row = horizonRow - k.fyPx * (grid.height(i, j) - camZ) / z;
        // The first row at or below `row` (integer arithmetic: a library call per sample would
        // slow the comparison down)
        const int whole = row > 0.0 ? static_cast<int>(row) : 0;
        const int from = row > 0.0 ? whole + (row > whole) : 0;
        if (from >= top) continue;
        const std::uint32_t c = grid.colour(i, j);
        for (int v = from; v < top; ++v) {
          std::uint8_t* px = &rgb[3 * (static_cast<std::size_t>(v) * static_cast<std::size_t>(k.widthPx) + u)];
          px[0] = static_cast<std::uint8_t>(c);
          px[1] = static_cast<std::uint8_t>(c >> 8);
          px[2] = static_cast<std::uint8_t>(c >> 16);
        }
        filled += static_cast<std::size_t>(top - from);
        top = from;
      }
    }
    shown += filled;
  });
  return shown;
}

}  // namespace fieldcast::core
