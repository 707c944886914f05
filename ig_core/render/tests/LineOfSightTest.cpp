// The line-of-sight march against a brute-force march of the same level-0 surface.
#include <ig_core/LineOfSight.h>

#include "RenderTestUtil.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <thread>

namespace fieldcast::core {
namespace {

using test::hills;

// First point below the level-0 surface in steps of 1/64 voxel: slow and plain.
double bruteForceRange(const TerrainView& view, const glm::dvec3& o, const glm::dvec3& d, double maxRangeM) {
  const double step = view.geometry().spacingM / 64.0;
  for (double t = 0.0; t <= maxRangeM; t += step) {
    const glm::dvec3 p = o + t * d;
    if (p.z <= view.heightAtM(p.x, p.y, 0)) return t;
  }
  return -1.0;
}

glm::dvec3 directionOf(double azimuthDeg, double elevationDeg) {
  const double az = radians(azimuthDeg), el = radians(elevationDeg);
  return {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)};
}

TEST(LineOfSight, RangesAgreeWithABruteForceMarchWithinOneVoxel) {
  const TerrainView& view = hills().view();
  const double voxel = view.geometry().spacingM;
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> where(100.0, 900.0), azimuth(0.0, 360.0), elevation(-30.0, -0.5),
      height(2.0, 150.0);
  int hits = 0;
  for (int k = 0; k < 200; ++k) {
    const double x = where(rng), y = where(rng);
    const glm::dvec3 o{x, y, view.heightAtM(x, y, 0) + height(rng)};
    const glm::dvec3 d = directionOf(azimuth(rng), elevation(rng));
    const double expected = bruteForceRange(view, o, d, 3000.0);
    const LineOfSightHit h = lineOfSight(view, o, d, 0.0, 3000.0);
    if (expected < 0.0) {
      // The brute force left the grid (its edge voxels extend): the march stops at the hull.
      continue;
    }
    const glm::dvec3 p = o + expected * d;
    const TerrainGeometry& g = view.geometry();
    if (p.x < g.originM.x || p.y < g.originM.y || p.x > g.originM.x + (g.widthVox - 1) * voxel ||
        p.y > g.originM.y + (g.heightVox - 1) * voxel) {
      continue;
    }
    ASSERT_TRUE(h.hit) << "ray " << k;
    ++hits;
    EXPECT_NEAR(h.rangeM, expected, voxel) << "ray " << k;
    // On the surface (bisection), the point and the range agree, the normal faces up.
    EXPECT_NEAR(h.pointM.z, view.heightAtM(h.pointM.x, h.pointM.y, 0), 1e-4) << "ray " << k;
    EXPECT_NEAR(glm::length(h.pointM - o), h.rangeM, 1e-6);
    EXPECT_NEAR(glm::length(h.normal), 1.0, 1e-9);
    EXPECT_GT(h.normal.z, 0.0);
  }
  EXPECT_GT(hits, 100);  // the rest leave the 1 km square first
}

TEST(LineOfSight, RangeLimitsAndUpwardRays) {
  const TerrainView& view = hills().view();
  const glm::dvec3 o{500.0, 500.0, view.heightAtM(500.0, 500.0, 0) + 50.0};
  const glm::dvec3 down{0.0, 0.0, -1.0};
  const LineOfSightHit h = lineOfSight(view, o, down, 0.0, 1000.0);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.rangeM, 50.0, 1e-4);
  EXPECT_FALSE(lineOfSight(view, o, down, 0.0, 49.0).hit);            // stops short of the ground
  EXPECT_FALSE(lineOfSight(view, o, {0.3, 0.2, 1.0}, 0.0, 1e5).hit);  // into the sky
  // A minimum range past the ground: the march starts below the surface and hits there.
  const LineOfSightHit under = lineOfSight(view, o, down, 60.0, 1000.0);
  ASSERT_TRUE(under.hit);
  EXPECT_NEAR(under.rangeM, 60.0, 1e-9);
}

// A host's "unlimited" range (FLT_MAX, infinity, 1e20 m) on a ray straight up or down: the x and
// y slabs bound nothing there, and the march's steps no longer moved a range that large, so the
// call never returned (the host link's thread hung on it). Run on a thread, so a hang fails here.
TEST(LineOfSight, AnUnlimitedRangeStraightUpOrDownEnds) {
  const TerrainView& view = hills().view();
  const glm::dvec3 o{500.0, 500.0, view.heightAtM(500.0, 500.0, 0) + 50.0};
  for (const double range :
       {1e20, static_cast<double>(std::numeric_limits<float>::max()), std::numeric_limits<double>::infinity()}) {
    for (const glm::dvec3& d : {directionOf(0.0, 90.0), glm::dvec3{0.0, 0.0, 1.0}, directionOf(0.0, -90.0)}) {
      auto done = std::make_shared<std::atomic<bool>>(false);
      auto hit = std::make_shared<LineOfSightHit>();
      std::thread([&view, o, d, range, done, hit] {
        *hit = lineOfSight(view, o, d, 0.0, range);
        done->store(true);
      }).detach();  // a march that never ends is left running; the test fails below
      for (int i = 0; i < 1000 && !done->load(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      ASSERT_TRUE(done->load()) << "range " << range << ", direction z " << d.z << ": the march did not end";
      EXPECT_EQ(hit->hit, d.z < 0.0) << range << " " << d.z;
      if (d.z < 0.0) EXPECT_NEAR(hit->rangeM, 50.0, 1e-4) << range;
    }
  }
}

TEST(LineOfSight, ColourIsTheLevelZeroColourAtTheVoxelCentre) {
  const TerrainView& view = hills().view();
  const TerrainGeometry& g = view.geometry();
  // Straight down onto voxel (200, 300)'s centre: its own colour, unblended.
  const glm::dvec3 centre{g.originM.x + 200 * g.spacingM, g.originM.y + 300 * g.spacingM, 0.0};
  const LineOfSightHit h =
      lineOfSight(view, {centre.x, centre.y, view.heightAtM(centre.x, centre.y, 0) + 30.0}, {0, 0, -1}, 0.0, 100.0);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.colourRgba, view.colourRgba(0, 200, 300));
}

TEST(LineOfSight, TilesAlongTheSegmentCoverItsEnds) {
  const TerrainGeometry& g = hills().view().geometry();  // 64-voxel tiles at 2 m: 128 m
  const auto tiles = lineOfSightTiles(g, {10.0, 10.0, 100.0}, {1000.0, 10.0, 0.0});
  const auto has = [&](int tx, int ty) {
    return std::find(tiles.begin(), tiles.end(), glm::ivec2(tx, ty)) != tiles.end();
  };
  for (int tx = 0; tx <= 7; ++tx) EXPECT_TRUE(has(tx, 0)) << tx;
  EXPECT_FALSE(has(0, 1));
}

// A track that clips a tile's corner: the tile's voxels are read there, so it is listed. Checked
// against the tiles of the four voxels around points every 1/64 voxel along 300 random tracks.
TEST(LineOfSight, TilesIncludeEveryCornerTheTrackClips) {
  const TerrainGeometry& g = hills().view().geometry();  // 64-voxel tiles at 2 m: 128 m
  const auto corner = lineOfSightTiles(g, {100.0, 170.0, 50.0}, {170.0, 100.0, 50.0});
  EXPECT_NE(std::find(corner.begin(), corner.end(), glm::ivec2(1, 1)), corner.end());

  std::mt19937 random(11);
  std::uniform_real_distribution<double> where(-50.0, g.spacingM * g.widthVox + 50.0);
  for (int n = 0; n < 300; ++n) {
    const glm::dvec3 from{where(random), where(random), 0.0}, to{where(random), where(random), 0.0};
    const auto tiles = lineOfSightTiles(g, from, to);
    const double length = std::hypot(to.x - from.x, to.y - from.y);
    const int samples = static_cast<int>(length / (g.spacingM / 64.0)) + 1;
    for (int s = 0; s <= samples; ++s) {
      const glm::dvec3 p = from + (to - from) * (static_cast<double>(s) / samples);
      const double fi = (p.x - g.originM.x) / g.spacingM, fj = (p.y - g.originM.y) / g.spacingM;
      if (fi < -1.0 || fj < -1.0 || fi > g.widthVox || fj > g.heightVox) continue;
      for (int k = 0; k < 4; ++k) {
        const int i = std::clamp(static_cast<int>(std::floor(fi)) + (k & 1), 0, g.widthVox - 1);
        const int j = std::clamp(static_cast<int>(std::floor(fj)) + (k >> 1), 0, g.heightVox - 1);
        const glm::ivec2 tile{i >> g.tileShift, j >> g.tileShift};
        ASSERT_NE(std::find(tiles.begin(), tiles.end(), tile), tiles.end())
            << "track " << n << " reads tile " << tile.x << "," << tile.y << " at sample " << s;
      }
    }
  }
}

}  // namespace
}  // namespace fieldcast::core
