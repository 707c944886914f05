#include <ig_core/MemoryTerrain.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

namespace fieldcast::core {
namespace {

struct Grid {
  TerrainGeometry geometry;
  std::vector<std::uint16_t> heights;
  std::vector<std::uint32_t> colours;
};

// An odd-sized random grid so edge clamping is exercised at every level.
Grid randomGrid(int w, int h, int tileShift, std::uint32_t seed) {
  Grid g;
  g.geometry.widthVox = w;
  g.geometry.heightVox = h;
  g.geometry.tileShift = tileShift;
  g.geometry.levels = 0;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> height(0, 4000);
  for (int k = 0; k < w * h; ++k) {
    g.heights.push_back(static_cast<std::uint16_t>(height(rng)));
    g.colours.push_back(static_cast<std::uint32_t>(rng()));
  }
  return g;
}

TEST(TerrainView, LevelZeroReturnsTheInputVoxels) {
  Grid g = randomGrid(37, 29, 3, 1);
  MemoryTerrain terrain(g.geometry, g.heights, g.colours);
  const TerrainView& view = terrain.view();
  for (int j = 0; j < 29; ++j) {
    for (int i = 0; i < 37; ++i) {
      EXPECT_EQ(view.heightQ(0, i, j), g.heights[static_cast<std::size_t>(j * 37 + i)]);
      EXPECT_EQ(view.colourRgba(0, i, j), g.colours[static_cast<std::size_t>(j * 37 + i)]);
    }
  }
  EXPECT_EQ(view.missCount(), 0u);
}

TEST(TerrainView, PyramidHasEnoughLevelsToFitOneTile) {
  Grid g = randomGrid(100, 40, 3, 2);
  MemoryTerrain terrain(g.geometry, g.heights, g.colours);
  const TerrainGeometry& geo = terrain.geometry();
  EXPECT_EQ(geo.levels, 5);  // 100 → 50 → 25 → 13 → 7 ≤ 8
  EXPECT_EQ(geo.levelWidthVox(4), 7);
  EXPECT_EQ(geo.tilesX(4), 1);
}

TEST(TerrainView, CoarseLevelAveragesItsChildren) {
  Grid g = randomGrid(16, 16, 2, 3);
  MemoryTerrain terrain(g.geometry, g.heights, g.colours);
  const auto h = [&](int i, int j) { return static_cast<unsigned>(g.heights[static_cast<std::size_t>(j * 16 + i)]); };
  const unsigned sum = h(4, 6) + h(5, 6) + h(4, 7) + h(5, 7);
  EXPECT_EQ(terrain.view().heightQ(1, 2, 3), (sum + 2) / 4);
}

// The max mip must bound every voxel of the levels at or below it within one voxel of the cell,
// or the renderer's empty-space skipping would step through hills.
TEST(TerrainView, MaxMipBoundsTheNeighbourhoodAtEveryLevel) {
  Grid g = randomGrid(45, 33, 2, 4);
  MemoryTerrain terrain(g.geometry, g.heights, g.colours);
  const TerrainView& view = terrain.view();
  const TerrainGeometry& geo = terrain.geometry();
  for (int level = 0; level < geo.levels; ++level) {
    for (int j = 0; j < geo.levelHeightVox(level); ++j) {
      for (int i = 0; i < geo.levelWidthVox(level); ++i) {
        const std::uint16_t bound = view.maxHeightQ(level, i, j);
        for (int fine = 0; fine <= level; ++fine) {
          const int scale = 1 << (level - fine);
          // Fine voxels whose centre lies within one coarse voxel of (i, j).
          for (int fj = (j - 1) * scale; fj < (j + 2) * scale; ++fj) {
            for (int fi = (i - 1) * scale; fi < (i + 2) * scale; ++fi) {
              if (fi < 0 || fj < 0 || fi >= geo.levelWidthVox(fine) || fj >= geo.levelHeightVox(fine)) continue;
              ASSERT_LE(view.heightQ(fine, fi, fj), bound) << "level " << level << " (" << i << "," << j << ")";
            }
          }
        }
      }
    }
  }
}

TEST(TerrainView, MissingTileIsAnsweredByACoarserLevelAndCounted) {
  Grid g = randomGrid(32, 32, 3, 5);
  MemoryTerrain terrain(g.geometry, g.heights, g.colours);
  const TerrainView& view = terrain.view();
  const TerrainView::Sample coarse = view.sample(1, 2, 2);
  const_cast<TerrainView&>(view).publish(0, 0, 0, nullptr);
  const TerrainView::Sample s = view.sample(0, 5, 5);
  EXPECT_EQ(s.level, 1);
  EXPECT_EQ(s.heightQ, coarse.heightQ);
  EXPECT_EQ(view.missCount(), 1u);
}

TEST(TerrainView, HeightAtVoxelCentresAndBetween) {
  Grid g = randomGrid(8, 8, 3, 6);
  g.geometry.spacingM = 2.0;
  g.geometry.originM = {100.0, 200.0};
  g.geometry.heightBaseM = -10.0;
  g.geometry.heightStepM = 0.5;
  MemoryTerrain terrain(g.geometry, g.heights, g.colours);
  const TerrainView& view = terrain.view();
  EXPECT_DOUBLE_EQ(view.heightAtM(100.0 + 2 * 3, 200.0 + 2 * 5), -10.0 + 0.5 * g.heights[5 * 8 + 3]);
  const double mid = -10.0 + 0.5 * 0.5 * (g.heights[5 * 8 + 3] + g.heights[5 * 8 + 4]);
  EXPECT_NEAR(view.heightAtM(100.0 + 7.0, 200.0 + 10.0), mid, 1e-9);
  // Level 1 voxel (1, 2) is centred half way between level-0 voxels 2,3 and 4,5.
  EXPECT_NEAR(view.heightAtM(100.0 + 2 * 2.5, 200.0 + 2 * 4.5, 1), -10.0 + 0.5 * view.heightQ(1, 1, 2), 1e-9);
}

TEST(TerrainView, RejectsAbsurdGeometry) {
  TerrainGeometry bad;
  bad.widthVox = 0;
  bad.heightVox = 10;
  EXPECT_THROW(TerrainView{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace fieldcast::core
