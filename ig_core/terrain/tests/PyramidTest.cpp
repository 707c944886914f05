// The pyramid built on several threads: every level checked against its definition (the box
// filter of the level below, the max mip as the 3×3 dilation of the block maxima of level 0) on a
// grid large enough that the finer levels' rows are shared out in several chunks, and the same
// bytes for any thread count.
#include <ig_core/Pyramid.h>

#include "TerrainTestUtil.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace fieldcast::core {
namespace {

using testing::randomTerrainGrid;

// Odd sides (edge clamping at every level) and 1001 voxels a row: 65 rows a chunk at level 0
TerrainGrid gridWithScatteredSticks() {
  TerrainGrid grid = randomTerrainGrid(1001, 1333, 24);
  grid.geometry.levels = 6;
  grid.stickId.assign(grid.heightQ.size(), 0u);
  for (std::size_t k = 0; k < grid.stickId.size(); k += 37) {
    grid.stickId[k] = 1 + static_cast<std::uint32_t>(k % 5);
    grid.heightQ[k] = static_cast<std::uint16_t>(grid.heightQ[k] + 400);  // the stick's top
  }
  return grid;
}

// The largest level-0 height in the voxels a coarse voxel covers (cut at the grid's edge)
std::uint16_t blockMax(const TerrainGrid& grid, int level, int i, int j) {
  const int w = grid.geometry.widthVox, h = grid.geometry.heightVox;
  std::uint16_t top = 0;
  for (int y = j << level; y < std::min((j + 1) << level, h); ++y) {
    for (int x = i << level; x < std::min((i + 1) << level, w); ++x) {
      top = std::max(top, grid.heightQ[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + x]);
    }
  }
  return top;
}

TEST(Pyramid, EveryLevelIsTheBoxFilterOfTheOneBelowWithAMaxMipOverItsNeighbours) {
  const TerrainGrid grid = gridWithScatteredSticks();
  const Pyramid pyramid = buildPyramid(grid.geometry, grid.heightQ, grid.colourRgba, {}, 2);
  ASSERT_EQ(pyramid.size(), 6u);
  EXPECT_EQ(pyramid[0].heightQ.data(), grid.heightQ.data()) << "level 0 is read in place, not copied";
  for (std::size_t level = 0; level < pyramid.size(); ++level) {
    const PyramidLevel& l = pyramid[level];
    const auto at = [&](int i, int j) {
      return static_cast<std::size_t>(j) * static_cast<std::size_t>(l.widthVox) + i;
    };
    for (int j = 0; j < l.heightVox; ++j) {
      for (int i = 0; i < l.widthVox; ++i) {
        std::uint16_t bound = 0;
        for (int dj = -1; dj <= 1; ++dj) {
          for (int di = -1; di <= 1; ++di) {
            bound = std::max(bound, blockMax(grid, static_cast<int>(level), std::clamp(i + di, 0, l.widthVox - 1),
                                             std::clamp(j + dj, 0, l.heightVox - 1)));
          }
        }
        ASSERT_EQ(l.maxHeightQ[at(i, j)], bound) << "level " << level << " voxel " << i << "," << j;
        if (level == 0) continue;
        const PyramidLevel& below = pyramid[level - 1];
        const auto child = [&](int a, int b) {
          return static_cast<std::size_t>(std::min(b, below.heightVox - 1)) * static_cast<std::size_t>(below.widthVox) +
                 static_cast<std::size_t>(std::min(a, below.widthVox - 1));
        };
        const std::size_t c[4] = {child(2 * i, 2 * j), child(2 * i + 1, 2 * j), child(2 * i, 2 * j + 1),
                                  child(2 * i + 1, 2 * j + 1)};
        const unsigned sum = below.heightQ[c[0]] + below.heightQ[c[1]] + below.heightQ[c[2]] + below.heightQ[c[3]];
        ASSERT_EQ(l.heightQ[at(i, j)], (sum + 2) / 4) << "level " << level << " voxel " << i << "," << j;
        const unsigned red = (below.colourRgba[c[0]] & 0xFFu) + (below.colourRgba[c[1]] & 0xFFu) +
                             (below.colourRgba[c[2]] & 0xFFu) + (below.colourRgba[c[3]] & 0xFFu);
        ASSERT_EQ(l.colourRgba[at(i, j)] & 0xFFu, (red + 2) / 4) << "level " << level << " voxel " << i << "," << j;
      }
    }
  }
}

TEST(Pyramid, AnyThreadCountBuildsTheSameBytes) {
  const TerrainGrid grid = gridWithScatteredSticks();
  const Pyramid one = buildPyramid(grid.geometry, grid.heightQ, grid.colourRgba, grid.stickId, 1);
  for (const int threads : {2, 3, 7}) {
    const Pyramid many = buildPyramid(grid.geometry, grid.heightQ, grid.colourRgba, grid.stickId, threads);
    ASSERT_EQ(many.size(), one.size());
    for (std::size_t level = 0; level < one.size(); ++level) {
      const auto same = [](auto a, auto b) { return std::equal(a.begin(), a.end(), b.begin(), b.end()); };
      EXPECT_TRUE(same(one[level].heightQ, many[level].heightQ)) << threads << " threads, level " << level;
      EXPECT_TRUE(same(one[level].maxHeightQ, many[level].maxHeightQ)) << threads << " threads, level " << level;
      EXPECT_TRUE(same(one[level].colourRgba, many[level].colourRgba)) << threads << " threads, level " << level;
      EXPECT_TRUE(same(one[level].stickId, many[level].stickId)) << threads << " threads, level " << level;
      EXPECT_FALSE(many[level].stickId.empty());
    }
  }
}

}  // namespace
}  // namespace fieldcast::core
