// No visible level-of-detail seam: on a flat plane textured with a smooth pattern plus a one-voxel
// checker (detail that only level 0 holds), the switch from one level to the next must not show
// as a step in the image. On a flat plane, seen without roll, an image row has one depth, so each
// level switch is a row boundary; the texture contrast of a row (mean |difference| between
// horizontally adjacent pixels) must change across a switch by no more than it changes between
// rows elsewhere.
#include "RenderTestUtil.h"

#include <ig_core/Renderer.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace fieldcast::core::test {
namespace {

struct SeamFigures {
  double worstSwitchStep = 0.0;  ///< largest contrast change across a level switch (grey levels)
  double typicalStep = 0.0;      ///< median contrast change between adjacent rows away from switches
  int switches = 0;
};

SeamFigures measureSeams(bool blend, double maxAnisotropy = 0.0) {
  static const std::unique_ptr<MemoryTerrain> plane = makeSyntheticTerrain({SyntheticKind::FlatPlane, 1024, 2.0, 6, 5});
  const TerrainView& view = plane->view();
  RenderSettings settings;
  settings.blendLevels = blend;
  settings.maxAnisotropy = maxAnisotropy;
  settings.colourMode = FrameColour::Grey;
  settings.rangeImage = true;
  settings.hazeRangeM = 0.0;
  settings.quality = 4.0;  // several switches within the 2 km plane
  Renderer renderer(view, settings, 2);
  ViewRequest r;
  r.pose = poseAbove(view, 1000.0, 200.0, 40.0, 0.0, -12.0);
  r.display = Intrinsics::fromHorizontalFov(320, 240, radians(50));
  const Frame f = renderer.render(r);
  const ViewGeometry geo(f.pose, f.intrinsics, view.geometry(), settings);
  const int w = f.image.widthPx();
  std::vector<double> contrast;
  std::vector<int> level;
  for (int y = 0; y < f.image.heightPx(); ++y) {
    const float range = f.rangeM[static_cast<std::size_t>(y * w + w / 2)];
    if (std::isinf(range)) continue;
    double sum = 0.0;
    for (int x = 0; x + 1 < w; ++x) sum += std::abs(f.image.row(y)[x + 1] - f.image.row(y)[x]);
    contrast.push_back(sum / (w - 1));
    const glm::dvec3 d = geo.ray(w / 2 + 0.5, y + 0.5);
    level.push_back(geo.lodLevel(range / glm::length(d), d));
  }
  if (std::getenv("FIELDCAST_DEBUG_SEAM")) {
    for (std::size_t k = 0; k < contrast.size(); ++k) std::printf("%zu L%d %.2f\n", k, level[k], contrast[k]);
  }
  // The march switches on the first even step past the depth, so the visible switch may lag the
  // nominal row by a step or two: look at every row step within three rows of each switch.
  SeamFigures s;
  std::vector<bool> nearSwitch(contrast.size(), false);
  for (std::size_t k = 0; k + 1 < contrast.size(); ++k) {
    if (level[k] == level[k + 1]) continue;
    ++s.switches;
    for (std::size_t m = k >= 3 ? k - 3 : 0; m <= k + 3 && m + 1 < contrast.size(); ++m) nearSwitch[m] = true;
  }
  std::vector<double> steps;
  for (std::size_t k = 0; k + 1 < contrast.size(); ++k) {
    const double step = std::abs(contrast[k + 1] - contrast[k]);
    if (nearSwitch[k]) {
      s.worstSwitchStep = std::max(s.worstSwitchStep, step);
    } else {
      steps.push_back(step);
    }
  }
  std::sort(steps.begin(), steps.end());
  s.typicalStep = steps.empty() ? 0.0 : steps[steps.size() / 2];
  return s;
}

TEST(LodSeam, BlendedLevelSwitchesShowNoContrastStep) {
  const SeamFigures blended = measureSeams(true);
  const SeamFigures hard = measureSeams(false);
  std::printf(
      "level switches: %d; contrast step across a switch: %.2f grey levels blended, %.2f unblended; "
      "median step between other rows %.2f\n",
      blended.switches, blended.worstSwitchStep, hard.worstSwitchStep, blended.typicalStep);
  ASSERT_GE(blended.switches, 3);
  // The bound: near a switch the row contrast may change by at most 2 grey levels per row (the
  // one-voxel checker alone is worth 100). Without blending the same scene breaks it.
  const double bound = 2.0;
  EXPECT_LE(blended.worstSwitchStep, bound);
  EXPECT_GT(hard.worstSwitchStep, bound);
}

// With the grazing-angle rule the levels switch at other rows (the depth is stretched by the ray's
// depression); the blend must follow the same stretched depth.
TEST(LodSeam, GrazingAngleLevelSwitchesShowNoContrastStep) {
  const SeamFigures blended = measureSeams(true, 2.0);
  const SeamFigures hard = measureSeams(false, 2.0);
  std::printf("grazing rule: %d level switches; step across a switch %.2f blended, %.2f unblended\n", blended.switches,
              blended.worstSwitchStep, hard.worstSwitchStep);
  ASSERT_GE(blended.switches, 3);
  EXPECT_LE(blended.worstSwitchStep, 2.0);
  EXPECT_GT(hard.worstSwitchStep, 2.0);
}

}  // namespace
}  // namespace fieldcast::core::test
