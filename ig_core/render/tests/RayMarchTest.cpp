// The per-ray march's two shortcuts tested directly: the first-hit descent of the max pyramid
// (firstHitStart) must find where a march from the ray's entry into the terrain would, and the
// backward retrace must take a ray whose coherent start lies below the surface back to the same
// first hit.
#include "ColumnCaster.h"
#include "RayMarch.h"
#include "RenderTestUtil.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace fieldcast::core::test {
namespace {

using ray_march::firstHitStart;
using ray_march::march;
using ray_march::marchCoherent;
using ray_march::MarchHit;
using ray_march::RayLine;
using ray_march::setupLine;
using ray_march::worldPoint;

// A pose's caster state, with the frame's rays at hand.
struct RayView {
  RenderSettings settings;
  Intrinsics k;
  ViewGeometry geo;
  CasterFrame frame;
  RayView(const TerrainView& view, const Pose& pose, double fovDeg)
      : k(Intrinsics::fromHorizontalFov(200, 150, radians(fovDeg))),
        geo(pose, k, view.geometry(), settings),
        frame(view, geo, settings, terrainCeilingQ(view), basePlaneColour(view), nullptr, nullptr) {}
};

// The same grid line of the same level, and the crossing within 1/100 of a voxel there (the march
// steps the ray's height in fixed point from where it starts: measured differences up to 0.003).
bool sameHit(const MarchHit& a, const MarchHit& b) {
  if (a.hit != b.hit) return false;
  return !a.hit ||
         (a.at.level == b.at.level && a.at.i == b.at.i && std::abs(a.m - b.m) <= 1e-2 * ray_march::pow2(a.at.level));
}

// Random rays over the hills, from 3 m to 2 km up, looking 1° to 80° down.
template <typename Check>
void forRandomRays(int count, unsigned seed, Check check) {
  const TerrainView& view = hills().view();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int n = 0; n < count; ++n) {
    const Pose pose = poseAbove(view, 100.0 + 800.0 * u01(rng), 100.0 + 800.0 * u01(rng),
                                std::exp(std::log(3.0) + u01(rng) * std::log(2000.0 / 3.0)), 360.0 * u01(rng),
                                -1.0 - 79.0 * u01(rng));
    const RayView v(view, pose, 20.0 + 70.0 * u01(rng));
    RayLine r;
    if (!setupLine(v.frame, v.geo.ray(200.0 * u01(rng), 150.0 * u01(rng)), r)) continue;
    check(v.frame, r);
  }
}

TEST(RayMarch, FirstHitDescentFindsTheHitOfTheMarchFromTheTerrainsEntry) {
  CasterThread t;
  int rays = 0, same = 0, skipped = 0;
  forRandomRays(3000, 11, [&](const CasterFrame& f, const RayLine& r) {
    const MarchHit full = march(f, t, r, r.mEnter);
    // (A hit before the first grid line is answered at the entry by a march from there.)
    if (full.hit && full.m <= r.mEnter + ray_march::pow2(full.at.level)) return;
    const double start = firstHitStart(f, r);
    const MarchHit fast = march(f, t, r, start);
    ++rays;
    if (sameHit(full, fast)) ++same;
    if (full.hit) {
      EXPECT_LE(start, full.m) << "the descent passed the first hit";
    }
    // Past at least 16 voxels of terrain that the ray provably clears.
    if (start > r.mEnter + 16.0) ++skipped;
  });
  std::printf("%d rays: %d same hit, %d started ≥ 16 voxels past the terrain's entry\n", rays, same, skipped);
  EXPECT_GT(rays, 2000);
  EXPECT_EQ(same, rays);
  EXPECT_GT(skipped, rays / 2);  // the descent does skip: returning the entry would pass the rest
}

// A one-voxel spike 100 m tall four voxels beside the ray's path, on flat ground: the coarse cells
// over the path contain the spike, so their max says the ray may hit there; the fine cells along the
// path say it does not. The descent must go down to them, pass the spike, and find the ground.
TEST(RayMarch, FirstHitDescentPassesACoarseCellWhoseFineCellsTheRayClears) {
  TerrainGeometry g;
  g.widthVox = g.heightVox = 256;
  g.spacingM = 1.0;
  g.heightStepM = 0.05;
  g.levels = 0;     // as many as fit
  g.tileShift = 4;  // 16-voxel tiles: five levels
  std::vector<std::uint16_t> heights(256 * 256, 0);
  std::vector<std::uint32_t> colours(256 * 256, 0xff808080u);
  heights[104 * 256 + 100] = 2000;  // (100, 104): 100 m
  const MemoryTerrain spike(g, heights, colours);
  const TerrainView& view = spike.view();
  // From (20, 100) at 50 m, looking east, down onto the ground at x = 200.
  Pose pose;
  pose.positionM = {20.0, 100.0, 50.0};
  pose.headingRad = radians(90.0);
  pose.pitchRad = -std::atan2(50.0, 180.0);
  const RayView v(view, pose, 20.0);  // narrow: level 0 out to about 570 m
  RayLine r;
  ASSERT_TRUE(setupLine(v.frame, v.geo.ray(v.k.cxPx, v.k.cyPx), r));
  ASSERT_TRUE(r.xMajor);
  // The coarse cells over the path at the spike do say "maybe" (the spike is within a voxel of
  // them, above the ray); the level-0 and level-1 cells do not.
  const double rayAtSpikeQ = v.frame.camZq + r.zPer * (100.0 - r.cMaj);
  ASSERT_EQ(view.levels(), 5);
  for (int level = 2; level < 5; ++level) ASSERT_GT(view.maxHeightQ(level, 100 >> level, 100 >> level), rayAtSpikeQ);
  for (int level = 0; level < 2; ++level) ASSERT_LT(view.maxHeightQ(level, 100 >> level, 100 >> level), rayAtSpikeQ);
  CasterThread t;
  const double start = firstHitStart(v.frame, r);
  const MarchHit full = march(v.frame, t, r, r.mEnter);
  const MarchHit fast = march(v.frame, t, r, start);
  ASSERT_TRUE(full.hit);
  EXPECT_GT(r.cMaj + start, 104.0) << "the descent stopped at the spike's coarse cell";
  EXPECT_LE(start, full.m);
  EXPECT_TRUE(sameHit(full, fast));
  EXPECT_NEAR(worldPoint(v.frame, r, fast.m).x, 200.0, 1.0);
}

// The ray below hit farther along than this ray's surface: its start lies under the terrain (a
// pitched column fans out in azimuth), and the march must walk back to the first hit.
TEST(RayMarch, BackwardRetraceFromAStartBelowTheSurfaceFindsTheFirstHit) {
  CasterThread t;
  int starts = 0, same = 0;
  std::uint64_t retraces = 0;
  forRandomRays(3000, 12, [&](const CasterFrame& f, const RayLine& r) {
    const MarchHit first = march(f, t, r, firstHitStart(f, r));
    if (!first.hit) return;
    // Start on the hit's own grid line (the march found it below the surface there) or the next.
    for (int beyond = 0; beyond < 2; ++beyond) {
      const double past = r.sx * ((first.at.i + r.sx * beyond + 0.5) * ray_march::pow2(first.at.level) - 0.5 - r.cMaj);
      if (past > r.mExit || f.geo->lodLevel(past / r.aMaj) != first.at.level) continue;
      bool havePrev = true;
      glm::dvec2 prevHit = r.xMajor ? glm::dvec2{r.cMaj + r.sx * past, r.cMin + r.slope * past}
                                    : glm::dvec2{r.cMin + r.slope * past, r.cMaj + r.sx * past};
      const std::uint64_t before = t.retraces;
      const MarchHit back = marchCoherent(f, t, r, havePrev, prevHit);
      ++starts;
      retraces += t.retraces - before;
      if (sameHit(first, back)) ++same;
    }
  });
  std::printf("%d starts below the surface: %d same hit, %llu retraced\n", starts, same,
              static_cast<unsigned long long>(retraces));
  EXPECT_GT(starts, 1000);
  // Every one but a rounding case or two (the march's fixed-point height there is a hair above the
  // surface) went through the retrace, and found the hit the forward march found.
  EXPECT_GE(retraces, static_cast<std::uint64_t>(starts - starts / 1000));
  EXPECT_GE(same, starts - starts / 200);
}

}  // namespace
}  // namespace fieldcast::core::test
