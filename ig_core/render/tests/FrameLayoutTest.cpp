#include <ig_core/RenderSettings.h>

#include <fieldcast/Pose.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace fieldcast::core {
namespace {

TEST(FrameLayout, DefaultMarginIsTenPercentOfEachDimensionPerSide) {
  const Intrinsics display = Intrinsics::fromHorizontalFov(720, 486, radians(60));
  const FrameLayout l = layoutFrame(display, 0.10, 0.0);
  EXPECT_EQ(l.margin.x, 72);
  EXPECT_EQ(l.margin.y, 49);  // 48.6 rounded up
  EXPECT_EQ(l.frame.widthPx, 864);
  EXPECT_EQ(l.frame.heightPx, 584);
  EXPECT_DOUBLE_EQ(l.frame.fxPx, display.fxPx);
  EXPECT_DOUBLE_EQ(l.frame.cxPx, display.cxPx + 72);
}

TEST(FrameLayout, RollGrowsTheFrameToCoverTheRotatedWindow) {
  const Intrinsics display = Intrinsics::fromHorizontalFov(400, 300, radians(60));
  const FrameLayout l = layoutFrame(display, 0.0, radians(90));
  // Rotated by 90°, the 400×300 window needs 300 wide... and 400 tall: 50 more rows each side.
  EXPECT_EQ(l.margin.x, 0);
  EXPECT_EQ(l.margin.y, 50);
  const FrameLayout small = layoutFrame(display, 0.1, radians(10));
  // Every rotated corner lies inside the frame.
  const double c = std::cos(radians(10)), s = std::sin(radians(10));
  for (const double u : {-200.0, 200.0}) {
    for (const double v : {-150.0, 150.0}) {
      EXPECT_LE(std::abs(c * u - s * v), small.frame.widthPx / 2.0);
      EXPECT_LE(std::abs(s * u + c * v), small.frame.heightPx / 2.0);
    }
  }
  EXPECT_GE(small.margin.x, 40);
}

TEST(FrameFootprint, ALevelFrameIsWhole) {
  const Intrinsics display = Intrinsics::fromHorizontalFov(720, 486, radians(60));
  const FrameLayout l = layoutFrame(display, 0.10, 0.0);
  EXPECT_TRUE(l.footprint.whole);
  const RowRun run = l.footprint.rows(0);
  EXPECT_EQ(run.first, 0);
  EXPECT_EQ(run.end, l.frame.heightPx);
  EXPECT_FALSE(layoutFrame(display, 0.10, radians(3.0)).footprint.whole);
}

// Every point of the turned, grown window that lies in the frame is in the footprint, with the
// four pixels a bilinear sample there reads among its columns' rows; the rows rendered are those
// pixels and at most a few rows more per column.
TEST(FrameFootprint, HoldsTheTurnedWindowAndItsMarginsAndLittleMore) {
  const Intrinsics display = Intrinsics::fromHorizontalFov(480, 270, radians(60));
  int outsideChecked = 0;
  for (const double rollDeg : {5.0, 30.0, 58.7, 90.0, 135.0, -40.0, 170.0}) {
    const FrameLayout l = layoutFrame(display, 0.10, radians(rollDeg));
    const FrameFootprint& fp = l.footprint;
    ASSERT_FALSE(fp.whole) << rollDeg;
    const int w = l.frame.widthPx, h = l.frame.heightPx;
    std::vector<RowRun> runs;
    for (int u = 0; u < w; ++u) runs.push_back(fp.rows(u));
    const double c = std::cos(radians(rollDeg)), s = std::sin(radians(rollDeg));
    // The window grown by 10% per side (288 × 162 px half-sizes), sampled every 0.7 px or so,
    // edges included (the contains test only inside them: on an edge rounding decides)
    constexpr double kHalfW = 240.0 + 48.0, kHalfH = 135.0 + 27.0;
    constexpr int kSteps = 823;
    for (int i = 0; i <= kSteps; ++i) {
      for (int j = 0; j <= kSteps * 9 / 16; ++j) {
        const double dx = -kHalfW + 2.0 * kHalfW * i / kSteps, dy = -kHalfH + 2.0 * kHalfH * j / (kSteps * 9 / 16);
        const glm::dvec2 p{l.frame.cxPx + c * dx - s * dy, l.frame.cyPx + s * dx + c * dy};
        if (p.x < 0.0 || p.x > w || p.y < 0.0 || p.y > h) continue;
        const bool onEdge = i == 0 || i == kSteps || j == 0 || j == kSteps * 9 / 16;
        if (!onEdge) {
          ASSERT_TRUE(fp.contains(p)) << rollDeg << "° at " << p.x << "," << p.y;
        }
        const int u0 = static_cast<int>(std::floor(p.x - 0.5)), v0 = static_cast<int>(std::floor(p.y - 0.5));
        for (int u = std::max(u0, 0); u <= std::min(u0 + 1, w - 1); ++u) {
          for (int v = std::max(v0, 0); v <= std::min(v0 + 1, h - 1); ++v) {
            ASSERT_TRUE(v >= runs[u].first && v < runs[u].end)
                << rollDeg << "°: column " << u << " rows " << runs[u].first << "-" << runs[u].end << " miss " << v;
          }
        }
      }
    }
    // A pixel beyond the grown window's edges, where in the frame: not in the footprint
    for (const glm::dvec2 d : {glm::dvec2{kHalfW + 1.0, 0.0}, glm::dvec2{-kHalfW - 1.0, 30.0},
                               glm::dvec2{0.0, kHalfH + 1.0}, glm::dvec2{-50.0, -kHalfH - 1.0}}) {
      const glm::dvec2 p{l.frame.cxPx + c * d.x - s * d.y, l.frame.cyPx + s * d.x + c * d.y};
      if (p.x < 0.0 || p.x > w || p.y < 0.0 || p.y > h) continue;
      ++outsideChecked;
      EXPECT_FALSE(fp.contains(p)) << rollDeg << "° at " << p.x << "," << p.y;
    }
    EXPECT_FALSE(fp.contains({std::nan(""), l.frame.cyPx}));
    // Rows rendered against the footprint's pixels in the frame
    std::size_t rendered = 0, inside = 0;
    for (int u = 0; u < w; ++u) {
      ASSERT_LT(runs[u].first, runs[u].end);
      rendered += static_cast<std::size_t>(runs[u].end - runs[u].first);
      for (int v = 0; v < h; ++v) inside += fp.contains({u + 0.5, v + 0.5}) ? 1 : 0;
    }
    EXPECT_LE(rendered, inside + 8 * static_cast<std::size_t>(w)) << rollDeg;
    if (std::abs(rollDeg) >= 30.0 && std::abs(rollDeg) <= 135.0) {
      EXPECT_LT(rendered, static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3 / 4) << rollDeg;
    }
  }
  EXPECT_GT(outsideChecked, 10);
}

// The side screen of a flat wall (README, Channels): its window lies wholly off the axis the roll
// turns it about, so the frame grows to 4.5× its pixels at 30° of roll and 9× at 90°; the
// footprint stays near the window and its margins (1.44× its pixels).
TEST(FrameFootprint, AnOffAxisWindowRendersLittleMoreThanItsOwnPixelsWhenRolled) {
  const Intrinsics display =
      Intrinsics::fromFrustum(720, 486, FrustumAngles{radians(26.57), radians(56.31), radians(31.0), radians(-31.0)});
  for (const double rollDeg : {30.0, 90.0}) {
    const FrameLayout l = layoutFrame(display, 0.10, radians(rollDeg));
    double rendered = 0.0;
    for (int u = 0; u < l.frame.widthPx; ++u) rendered += l.footprint.rows(u).end - l.footprint.rows(u).first;
    const double windowPx = 720.0 * 486.0;
    const double framePx = static_cast<double>(l.frame.widthPx) * l.frame.heightPx;
    std::printf("roll %.0f°: frame %dx%d = %.2f× the window's pixels, footprint %.2f×\n", rollDeg, l.frame.widthPx,
                l.frame.heightPx, framePx / windowPx, rendered / windowPx);
    EXPECT_GT(framePx / windowPx, 4.0);
    EXPECT_LT(rendered / windowPx, 1.6);
  }
}

}  // namespace
}  // namespace fieldcast::core
