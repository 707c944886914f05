#include <ig_core/RenderSettings.h>

#include <fieldcast/Pose.h>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace fieldcast::core
