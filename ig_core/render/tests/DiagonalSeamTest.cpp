// Looking along a grid diagonal, the columns on either side march along different axes (each
// column's plane takes the axis its ground trace runs closer to). Close up over coarse data, where a
// voxel spans many pixels, the image must not change from one to the other in one column.
#include "LaneMarch.h"
#include "RenderTestUtil.h"

#include <ig_core/Renderer.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <tuple>
#include <vector>

namespace fieldcast::core::test {
namespace {

// 30 m voxels, so that from 25 m up a voxel spans tens of pixels.
const MemoryTerrain& coarseHills() {
  static const std::unique_ptr<MemoryTerrain> t = makeSyntheticTerrain({SyntheticKind::Hills, 256, 30.0, 6, 5});
  return *t;
}

double grey(const Frame& f, int u, int v) {
  const std::uint8_t* p = f.image.row(v) + 3 * u;
  return (p[0] + p[1] + p[2]) / 3.0;
}

// Mean over the rows of |2·I(u) − I(u−1) − I(u+1)| per column u: a step between two columns shows
// in both.
std::vector<double> columnSecondDifference(const Frame& f) {
  std::vector<double> d(static_cast<std::size_t>(f.image.widthPx()), 0.0);
  for (int u = 1; u + 1 < f.image.widthPx(); ++u) {
    double sum = 0.0;
    for (int v = 0; v < f.image.heightPx(); ++v)
      sum += std::abs(2 * grey(f, u, v) - grey(f, u - 1, v) - grey(f, u + 1, v));
    d[static_cast<std::size_t>(u)] = sum / f.image.heightPx();
  }
  return d;
}

// Headings on the four diagonals and one just off one. The 81-pixel display has a 99-pixel frame
// whose column 49 looks exactly along the heading; the columns' major axis changes there. Before the
// fill was split at the crossings of the minor axis's grid lines, columns 49 and 50 stood at 2.2 to
// 4.4 against a median of 0.6 to 1.0 for the others (2.5 to 5.8 times); now columns 48 to 51 are
// at most 1.4 times the median.
void diagonalColumnsMatchTheirNeighbours(bool laneMarch) {
  const TerrainView& view = coarseHills().view();
  RenderSettings settings;
  settings.laneMarch = laneMarch;
  Renderer renderer(view, settings, 1);
  for (const double heading : {45.0, 135.0, 225.0, 315.0, 44.99}) {
    ViewRequest request;
    request.pose = poseAbove(view, 3800.0, 3900.0, 25.0, heading, -12.0);
    request.display = Intrinsics::fromHorizontalFov(81, 60, radians(40.0));
    const Frame f = renderer.render(request);
    ASSERT_EQ(f.intrinsics.cxPx, 49.5);
    std::vector<double> d = columnSecondDifference(f);
    const double seam = std::max({d[48], d[49], d[50], d[51]});
    std::vector<double> others(d.begin() + 1, d.end() - 1);
    std::nth_element(others.begin(), others.begin() + others.size() / 2, others.end());
    const double median = others[others.size() / 2];
    std::printf("heading %.2f: columns 48..51 %.2f %.2f %.2f %.2f, median column %.2f\n", heading, d[48], d[49], d[50],
                d[51], median);
    EXPECT_LE(seam, 2.0 * median) << "heading " << heading;
  }
}

TEST(DiagonalSeam, ColumnsAlongAGridDiagonalMatchTheirNeighbours) { diagonalColumnsMatchTheirNeighbours(false); }

TEST(DiagonalSeam, ColumnsAlongAGridDiagonalMatchTheirNeighboursInTheLaneMarch) {
  diagonalColumnsMatchTheirNeighbours(true);
}

// The lane march shares a level across each block of kLaneColumns (eight) columns, switching where all of them
// would: a block's columns may be drawn finer than their neighbours' in the next block. On the
// hills, at the views of the accuracy sweep's kinds, the columns at the blocks' edges must not
// stand out from the others.
TEST(DiagonalSeam, LaneBlocksShowNoSeamAtTheirEdges) {
  const TerrainView& view = hills().view();
  RenderSettings settings;
  settings.laneMarch = true;
  Renderer renderer(view, settings, 1);
  for (const auto& [heading, pitch, altitude] :
       {std::tuple{10.0, -15.0, 80.0}, {200.0, -60.0, 400.0}, {290.0, -3.0, 25.0}, {135.0, -30.0, 1500.0}}) {
    ViewRequest request;
    request.pose = poseAbove(view, 500.0, 470.0, altitude, heading, pitch);
    request.display = Intrinsics::fromHorizontalFov(200, 150, radians(60.0));
    const Frame f = renderer.render(request);
    const std::vector<double> d = columnSecondDifference(f);
    double edges = 0.0, others = 0.0;
    int edgeCount = 0, otherCount = 0;
    for (int u = 1; u + 1 < f.image.widthPx(); ++u) {
      // A step between a block's last column and the next block's first shows in both
      constexpr int kBlock = plane_march::kLaneColumns;
      const bool edge = u % kBlock == 0 || u % kBlock == kBlock - 1;
      (edge ? edges : others) += d[static_cast<std::size_t>(u)];
      ++(edge ? edgeCount : otherCount);
    }
    edges /= edgeCount;
    others /= otherCount;
    std::printf("heading %.0f pitch %.0f: block edges %.3f, other columns %.3f\n", heading, pitch, edges, others);
    EXPECT_LE(edges, 1.1 * others) << "heading " << heading;
  }
}

}  // namespace
}  // namespace fieldcast::core::test
