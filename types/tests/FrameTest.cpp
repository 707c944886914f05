#include <fieldcast/Frame.h>

#include <gtest/gtest.h>

#include <stdexcept>

namespace fieldcast {
namespace {

TEST(ControlGrid, NinePointsSpreadOverTheDisplayWindow) {
  const auto points = controlGridFramePx(720, 486, MarginPx{72, 49});
  ASSERT_EQ(points.size(), 9u);
  // Row-major, top-left first, inset 5% from each edge of the display window.
  EXPECT_DOUBLE_EQ(points[0].x, 72 + 36.0);
  EXPECT_DOUBLE_EQ(points[0].y, 49 + 24.3);
  EXPECT_DOUBLE_EQ(points[4].x, 72 + 360.0);
  EXPECT_DOUBLE_EQ(points[4].y, 49 + 243.0);
  EXPECT_DOUBLE_EQ(points[8].x, 72 + 684.0);
  EXPECT_DOUBLE_EQ(points[8].y, 49 + 461.7);
}

TEST(ControlGrid, RejectsNonsense) {
  EXPECT_THROW(controlGridFramePx(100, 100, {}, 1), std::invalid_argument);
  EXPECT_THROW(controlGridFramePx(100, 100, {}, 3, 0.5), std::invalid_argument);
}

TEST(Frame, DisplayWindowIsFrameLessMargins) {
  Frame frame;
  frame.intrinsics = Intrinsics::fromHorizontalFov(720, 486, 1.0).withMargin(72, 49);
  frame.margin = {72, 49};
  EXPECT_EQ(frame.displayWidthPx(), 720);
  EXPECT_EQ(frame.displayHeightPx(), 486);
  EXPECT_FALSE(frame.hasRange());
}

}  // namespace
}  // namespace fieldcast
