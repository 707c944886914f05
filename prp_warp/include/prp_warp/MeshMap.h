#pragma once
// The depth-mesh warp's map: a regular grid of nodes over the output raster, each holding the
// frame pixel the field's camera sees at that node; between nodes the map is bilinear. A cell
// where bilinear is not close enough (the horizon, a ridge's silhouette) can be refined into
// kSubdivision × kSubdivision sub-cells with nodes of their own. Raster coordinates as in
// WarpMaps.h (pixel centres at half-integers).

#include <glm/vec2.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fieldcast::warp {

class MeshMap {
 public:
  /// Sub-cells per refined cell, along each axis.
  static constexpr int kSubdivision = 4;
  static constexpr int kSubNodes = kSubdivision + 1;

  MeshMap() = default;
  /// A node every `spacingPx` raster pixels over a raster `widthPx` × `heightPx`, the last row
  /// and column of nodes on the raster's far edges; room to refine every cell. Allocates; every
  /// node starts at (0, 0), no cell refined.
  MeshMap(int widthPx, int heightPx, int spacingPx);

  int columns() const noexcept { return mColumns; }
  int rows() const noexcept { return mRows; }
  int spacingPx() const noexcept { return mSpacingPx; }

  /// Raster coordinate of node column `k` / node row `l` (integers: node k sits at k·spacing).
  int nodeXPx(int k) const noexcept { return k * mSpacingPx < mWidthPx ? k * mSpacingPx : mWidthPx; }
  int nodeYPx(int l) const noexcept { return l * mSpacingPx < mHeightPx ? l * mSpacingPx : mHeightPx; }

  /// The cell column (row) holding raster coordinate `u` (`v`); outside the raster, the edge cell.
  int cellColumn(double u) const noexcept { return cellOf(u, mColumns); }
  int cellRow(double v) const noexcept { return cellOf(v, mRows); }

  /// Frame pixel of node (k, l).
  float& frameX(int k, int l) noexcept { return mX[index(k, l)]; }
  float& frameY(int k, int l) noexcept { return mY[index(k, l)]; }
  float frameX(int k, int l) const noexcept { return mX[index(k, l)]; }
  float frameY(int k, int l) const noexcept { return mY[index(k, l)]; }

  /// Undoes every refinement. RT-safe.
  void clearRefinement() noexcept;
  /// Refines cell (k, l) (its top-left node); its sub-grid's corners take the cell's nodes, the
  /// other sub-nodes start bilinear. RT-safe (the room is allocated up front).
  void refine(int k, int l) noexcept;
  /// True when cell (k, l) is refined.
  bool refined(int k, int l) const noexcept { return mSubGrid[cellIndex(k, l)] >= 0; }
  int refinedCells() const noexcept { return mRefinedCells; }
  /// Raster position of sub-node (i, j) of cell (k, l), i, j in 0 … kSubdivision.
  glm::dvec2 subNodePx(int k, int l, int i, int j) const noexcept;
  /// Frame pixel of sub-node (i, j) of refined cell (k, l).
  float& subX(int k, int l, int i, int j) noexcept { return mSubX[subIndex(k, l, i, j)]; }
  float& subY(int k, int l, int i, int j) noexcept { return mSubY[subIndex(k, l, i, j)]; }
  float subX(int k, int l, int i, int j) const noexcept { return mSubX[subIndex(k, l, i, j)]; }
  float subY(int k, int l, int i, int j) const noexcept { return mSubY[subIndex(k, l, i, j)]; }

  /// Frame pixel sampled for raster pixel `rasterPx`: bilinear between the four nodes of its
  /// cell, or of its sub-cell in a refined cell (extrapolated linearly outside the raster).
  /// RT-safe.
  glm::dvec2 operator()(glm::dvec2 rasterPx) const noexcept;

 private:
  std::size_t index(int k, int l) const noexcept {
    return static_cast<std::size_t>(l) * static_cast<std::size_t>(mColumns) + static_cast<std::size_t>(k);
  }
  std::size_t cellIndex(int k, int l) const noexcept {
    return static_cast<std::size_t>(l) * static_cast<std::size_t>(mColumns - 1) + static_cast<std::size_t>(k);
  }
  std::size_t subIndex(int k, int l, int i, int j) const noexcept {
    return static_cast<std::size_t>(mSubGrid[cellIndex(k, l)]) * kSubNodes * kSubNodes +
           static_cast<std::size_t>(j * kSubNodes + i);
  }
  int cellOf(double coordinate, int nodes) const noexcept;
  /// Bilinear between the four nodes of cell (k, l) in node values `c`, at (s, t) of the cell.
  double cellBlend(const std::vector<float>& c, int k, int l, double s, double t) const noexcept;

  int mWidthPx = 0;
  int mHeightPx = 0;
  int mSpacingPx = 1;
  int mColumns = 0;
  int mRows = 0;
  std::vector<float> mX, mY;           // node-major: row l, column k at l·columns + k
  std::vector<std::int32_t> mSubGrid;  // per cell: its sub-grid's slot, or −1
  std::vector<float> mSubX, mSubY;     // kSubNodes² per slot, row-major
  int mRefinedCells = 0;
};

}  // namespace fieldcast::warp
