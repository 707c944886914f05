#include <ig_core/LineOfSight.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace fieldcast::core {
namespace {

// Bilinear RGBA8 of level 0 at continuous voxel coordinates (x, y), channel by channel.
std::uint32_t bilinearColour(const TerrainView& view, double x, double y) {
  const int i = static_cast<int>(std::floor(x));
  const int j = static_cast<int>(std::floor(y));
  const double tx = x - i;
  const double ty = y - j;
  const std::uint32_t c00 = view.colourRgba(0, i, j), c10 = view.colourRgba(0, i + 1, j);
  const std::uint32_t c01 = view.colourRgba(0, i, j + 1), c11 = view.colourRgba(0, i + 1, j + 1);
  std::uint32_t out = 0;
  for (int shift = 0; shift < 32; shift += 8) {
    const auto ch = [&](std::uint32_t c) { return static_cast<double>((c >> shift) & 0xFFu); };
    const double a = ch(c00) + tx * (ch(c10) - ch(c00));
    const double b = ch(c01) + tx * (ch(c11) - ch(c01));
    const auto v = static_cast<std::uint32_t>(std::lround(std::clamp(a + ty * (b - a), 0.0, 255.0)));
    out |= v << shift;
  }
  return out;
}

// The coarsest level empty space is skipped at (2^8 voxels a side): coarser voxels rarely lie
// wholly under a ray that is going to meet the terrain.
constexpr int kCoarsestSkipLevel = 8;
// How far past a voxel's exit a skip lands, so the next look is in the next voxel.
constexpr double kSkipPastM = 1e-6;

// The level-`level` voxel the ray is over at t, and the t where the ray leaves its area (the
// square of level-0 voxel centres it covers, widened by half a level-0 voxel each side).
struct VoxelSpan {
  int i = 0, j = 0;
  double exitT = 0.0;
};
VoxelSpan voxelSpanAt(const TerrainGeometry& g, const glm::dvec3& originM, const glm::dvec3& d, double t,
                      int level) noexcept {
  const double cell = g.spacingM * static_cast<double>(1 << level);
  const glm::dvec3 p = originM + t * d;
  const double x0 = g.originM.x - 0.5 * g.spacingM, y0 = g.originM.y - 0.5 * g.spacingM;
  VoxelSpan span;
  span.i = static_cast<int>(std::floor((p.x - x0) / cell));
  span.j = static_cast<int>(std::floor((p.y - y0) / cell));
  const auto exitAlong = [](double origin, double dir, double low, double high) {
    if (dir > 0.0) return (high - origin) / dir;
    if (dir < 0.0) return (low - origin) / dir;
    return std::numeric_limits<double>::infinity();
  };
  const double xLow = x0 + span.i * cell, yLow = y0 + span.j * cell;
  span.exitT = std::min(exitAlong(originM.x, d.x, xLow, xLow + cell), exitAlong(originM.y, d.y, yLow, yLow + cell));
  span.exitT = std::max(span.exitT, t);  // a point on the border rounds either way
  return span;
}

LineOfSightHit hitAt(const TerrainView& view, const glm::dvec3& originM, const glm::dvec3& d, double t) {
  const TerrainGeometry& g = view.geometry();
  LineOfSightHit h;
  h.hit = true;
  h.rangeM = t;
  h.pointM = originM + t * d;
  h.normal = surfaceNormalAt(view, h.pointM.x, h.pointM.y);
  h.colourRgba = bilinearColour(view, (h.pointM.x - g.originM.x) / g.spacingM, (h.pointM.y - g.originM.y) / g.spacingM);
  return h;
}

}  // namespace

glm::dvec3 surfaceNormalAt(const TerrainView& view, double xM, double yM) noexcept {
  const double d = 0.5 * view.geometry().spacingM;
  const double dzdx = (view.heightAtM(xM + d, yM, 0) - view.heightAtM(xM - d, yM, 0)) / (2 * d);
  const double dzdy = (view.heightAtM(xM, yM + d, 0) - view.heightAtM(xM, yM - d, 0)) / (2 * d);
  const glm::dvec3 n(-dzdx, -dzdy, 1.0);
  return n / std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
}

LineOfSightHit lineOfSight(const TerrainView& view, const glm::dvec3& originM, const glm::dvec3& direction,
                           double minRangeM, double maxRangeM) noexcept {
  const double length = std::sqrt(direction.x * direction.x + direction.y * direction.y + direction.z * direction.z);
  if (!(length > 0.0) || !(maxRangeM >= minRangeM)) return {};
  const glm::dvec3 d = direction / length;  // t is then the range in metres
  const TerrainGeometry& g = view.geometry();

  // Clip to the hull of the level-0 voxel centres (the max mip below skips the space above the
  // terrain: no whole-terrain ceiling scan per ray).
  double lo = std::max(minRangeM, 0.0);
  double hi = maxRangeM;
  const auto slab = [&](double origin, double dir, double minV, double maxV) {
    if (std::abs(dir) < 1e-15) return origin >= minV && origin <= maxV;
    const double a = (minV - origin) / dir;
    const double b = (maxV - origin) / dir;
    lo = std::max(lo, std::min(a, b));
    hi = std::min(hi, std::max(a, b));
    return true;
  };
  const double x1 = g.originM.x + (g.widthVox - 1) * g.spacingM;
  const double y1 = g.originM.y + (g.heightVox - 1) * g.spacingM;
  if (!slab(originM.x, d.x, g.originM.x, x1) || !slab(originM.y, d.y, g.originM.y, y1) || lo > hi) {
    return {};
  }
  // And to the heights a voxel can have, a step past each so the rounding of the ray's height
  // there cannot stop it short: a ray straight up or down crosses the x and y slabs nowhere, and a
  // range of 1e20 m or more (a host's "unlimited") was left to the march, whose steps no longer
  // moved t at that size. Past the top it meets nothing; past the bottom it has met the surface,
  // or started under it.
  const double lowest = g.heightM(0) - g.heightStepM;
  const double highest = g.heightM(std::numeric_limits<std::uint16_t>::max()) + g.heightStepM;
  if (d.z > 0.0) hi = std::min(hi, (highest - originM.z) / d.z);
  if (d.z < 0.0) hi = std::min(hi, std::max(lo, (lowest - originM.z) / d.z));
  if (lo > hi) return {};
  const auto above = [&](double t) {
    const glm::dvec3 p = originM + t * d;
    return p.z - view.heightAtM(p.x, p.y, 0);
  };
  double t = lo;
  if (above(t) <= 0.0) return hitAt(view, originM, d, t);
  // 1/8 voxel horizontally; steep rays also advance at most 1/8 voxel-height of drop per step.
  const double horizontal = std::sqrt(d.x * d.x + d.y * d.y);
  const double dt = 0.125 * g.spacingM / std::max(horizontal, 0.05 * std::abs(d.z) + 1e-12);
  const int coarsest = std::min(g.levels - 1, kCoarsestSkipLevel);
  while (t < hi) {
    // Empty space first: from the coarsest level down, the level-L voxel the ray is over bounds
    // the surface beneath it (max mip); a ray above that bound all the way across cannot meet
    // the surface there and jumps to where it leaves the voxel.
    double fineUntil = hi;
    bool skipped = false;
    for (int level = coarsest; level >= 1 && !skipped; --level) {
      const VoxelSpan span = voxelSpanAt(g, originM, d, t, level);
      const double end = std::min(span.exitT, hi);
      const double lowestZ = std::min(originM.z + t * d.z, originM.z + end * d.z);
      if (lowestZ > g.heightM(view.maxHeightQ(level, span.i, span.j))) {
        t = end + kSkipPastM;  // into the next voxel (the surface stays below the ray at `end`)
        skipped = true;
      } else if (level == 1) {
        fineUntil = end;  // the surface may rise to the ray here: march it finely
      }
    }
    if (skipped) {
      if (t >= hi) break;
      if (above(t) <= 0.0) return hitAt(view, originM, d, t);  // met within the skip's last micrometre
      continue;
    }
    // The plain march over this level-1 voxel: steps of dt, the crossing refined by bisection.
    do {
      const double tNext = std::min(t + dt, hi);
      if (above(tNext) <= 0.0) {
        double a = t;      // above the surface
        double b = tNext;  // on or below it
        for (int k = 0; k < 60 && (b - a) > 1e-7; ++k) {
          const double mid = 0.5 * (a + b);
          (above(mid) > 0.0 ? a : b) = mid;
        }
        return hitAt(view, originM, d, b);
      }
      t = tNext;
    } while (t < fineUntil && t < hi);
  }
  return {};
}

std::vector<glm::ivec2> lineOfSightTiles(const TerrainGeometry& g, const glm::dvec3& fromM, const glm::dvec3& toM) {
  // The bilinear surface at a point of cell (i, j) — the square between voxel centres i, i + 1 and
  // j, j + 1 — reads those four voxels. Walk every cell the segment's ground track crosses
  // (Amanatides and Woo's traversal, in voxel-centre units), clipped to the cells that read the
  // grid: a corner the track only clips is a cell too, and its voxels' tiles are listed.
  const glm::dvec2 a{(fromM.x - g.originM.x) / g.spacingM, (fromM.y - g.originM.y) / g.spacingM};
  const glm::dvec2 d = glm::dvec2{(toM.x - g.originM.x) / g.spacingM, (toM.y - g.originM.y) / g.spacingM} - a;
  const glm::dvec2 low{-1.0, -1.0}, high{static_cast<double>(g.widthVox), static_cast<double>(g.heightVox)};
  double u0 = 0.0, u1 = 1.0;
  for (int axis = 0; axis < 2; ++axis) {
    if (d[axis] == 0.0) {
      if (a[axis] < low[axis] || a[axis] > high[axis]) return {};
      continue;
    }
    const double e0 = (low[axis] - a[axis]) / d[axis], e1 = (high[axis] - a[axis]) / d[axis];
    u0 = std::max(u0, std::min(e0, e1));
    u1 = std::min(u1, std::max(e0, e1));
  }
  if (u0 > u1) return {};  // off the grid

  std::vector<glm::ivec2> tiles;
  const auto addCell = [&](int i, int j) {
    for (int k = 0; k < 4; ++k) {
      const int vi = std::clamp(i + (k & 1), 0, g.widthVox - 1);
      const int vj = std::clamp(j + (k >> 1), 0, g.heightVox - 1);
      tiles.emplace_back(vi >> g.tileShift, vj >> g.tileShift);
    }
  };
  const glm::dvec2 start = a + u0 * d;
  glm::ivec2 cell{static_cast<int>(std::floor(start.x)), static_cast<int>(std::floor(start.y))};
  const glm::ivec2 last{static_cast<int>(std::floor(a.x + u1 * d.x)), static_cast<int>(std::floor(a.y + u1 * d.y))};
  glm::ivec2 step{0, 0};
  glm::dvec2 next{std::numeric_limits<double>::infinity()}, delta{std::numeric_limits<double>::infinity()};
  for (int axis = 0; axis < 2; ++axis) {
    if (d[axis] == 0.0) continue;
    step[axis] = d[axis] > 0.0 ? 1 : -1;
    const double boundary = cell[axis] + (d[axis] > 0.0 ? 1.0 : 0.0);
    next[axis] = (boundary - a[axis]) / d[axis];
    delta[axis] = 1.0 / std::abs(d[axis]);
  }
  addCell(cell.x, cell.y);
  while (cell != last) {
    const int axis = next.x < next.y ? 0 : 1;
    if (next[axis] > u1) break;
    cell[axis] += step[axis];
    next[axis] += delta[axis];
    addCell(cell.x, cell.y);
  }
  std::sort(tiles.begin(), tiles.end(),
            [](const glm::ivec2& p, const glm::ivec2& q) { return p.x != q.x ? p.x < q.x : p.y < q.y; });
  tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
  return tiles;
}

}  // namespace fieldcast::core
