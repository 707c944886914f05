// The depth mesh's node grid and its bilinear evaluation (the reference every kernel follows).
#include <prp_warp/MeshMap.h>

#include <algorithm>
#include <cmath>

namespace fieldcast::warp {
namespace {

/// Bilinear between four corner values at (s, t) of their cell, s and t in [0, 1].
double bilinear(double c00, double c10, double c01, double c11, double s, double t) noexcept {
  const double top = c00 + s * (c10 - c00);
  const double bottom = c01 + s * (c11 - c01);
  return top + t * (bottom - top);
}

}  // namespace

MeshMap::MeshMap(int widthPx, int heightPx, int spacingPx)
    : mWidthPx(widthPx),
      mHeightPx(heightPx),
      mSpacingPx(spacingPx),
      mColumns((widthPx + spacingPx - 1) / spacingPx + 1),
      mRows((heightPx + spacingPx - 1) / spacingPx + 1),
      mX(static_cast<std::size_t>(mColumns) * static_cast<std::size_t>(mRows), 0.0f),
      mY(mX.size(), 0.0f),
      mSubGrid(static_cast<std::size_t>(mColumns - 1) * static_cast<std::size_t>(mRows - 1), -1),
      mSubX(mSubGrid.size() * kSubNodes * kSubNodes, 0.0f),
      mSubY(mSubX.size(), 0.0f) {}

int MeshMap::cellOf(double coordinate, int nodes) const noexcept {
  const double cell = std::floor(coordinate / mSpacingPx);
  if (!(cell > 0.0)) return 0;  // also NaN
  return static_cast<int>(std::min(cell, static_cast<double>(nodes - 2)));
}

void MeshMap::clearRefinement() noexcept {
  std::fill(mSubGrid.begin(), mSubGrid.end(), -1);
  mRefinedCells = 0;
}

double MeshMap::cellBlend(const std::vector<float>& c, int k, int l, double s, double t) const noexcept {
  return bilinear(c[index(k, l)], c[index(k + 1, l)], c[index(k, l + 1)], c[index(k + 1, l + 1)], s, t);
}

glm::dvec2 MeshMap::subNodePx(int k, int l, int i, int j) const noexcept {
  const double left = nodeXPx(k), right = nodeXPx(k + 1), top = nodeYPx(l), bottom = nodeYPx(l + 1);
  return {left + (right - left) * i / kSubdivision, top + (bottom - top) * j / kSubdivision};
}

void MeshMap::refine(int k, int l) noexcept {
  if (refined(k, l)) return;
  mSubGrid[cellIndex(k, l)] = mRefinedCells++;
  for (int j = 0; j < kSubNodes; ++j)
    for (int i = 0; i < kSubNodes; ++i) {
      const double s = static_cast<double>(i) / kSubdivision, t = static_cast<double>(j) / kSubdivision;
      subX(k, l, i, j) = static_cast<float>(cellBlend(mX, k, l, s, t));
      subY(k, l, i, j) = static_cast<float>(cellBlend(mY, k, l, s, t));
    }
}

glm::dvec2 MeshMap::operator()(glm::dvec2 rasterPx) const noexcept {
  const int k = cellColumn(rasterPx.x), l = cellRow(rasterPx.y);
  double s = (rasterPx.x - nodeXPx(k)) / (nodeXPx(k + 1) - nodeXPx(k));
  double t = (rasterPx.y - nodeYPx(l)) / (nodeYPx(l + 1) - nodeYPx(l));
  if (!refined(k, l)) return {cellBlend(mX, k, l, s, t), cellBlend(mY, k, l, s, t)};
  // The sub-cell, and the position within it
  auto subCell = [](double f) noexcept {
    if (!(f > 0.0)) return 0;  // also NaN
    return std::min(static_cast<int>(f * kSubdivision), kSubdivision - 1);
  };
  const int i = subCell(s), j = subCell(t);
  s = s * kSubdivision - i;
  t = t * kSubdivision - j;
  auto blend = [&](const std::vector<float>& c) noexcept {
    return bilinear(c[subIndex(k, l, i, j)], c[subIndex(k, l, i + 1, j)], c[subIndex(k, l, i, j + 1)],
                    c[subIndex(k, l, i + 1, j + 1)], s, t);
  };
  return {blend(mSubX), blend(mSubY)};
}

}  // namespace fieldcast::warp
