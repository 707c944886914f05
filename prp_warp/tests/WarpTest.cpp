// The warps through their common interface: identity, field rows and parity, fallbacks, bad input.
#include "AnalyticScene.h"

#include <prp_warp/FieldClock.h>
#include <prp_warp/Warps.h>

#include <gtest/gtest.h>

namespace fieldcast::warp {
namespace {

constexpr int kW = 160, kH = 120;
const MarginPx kMargin{16, 12};
const Pose kPose{{0.0, 0.0, 200.0}, radians(10.0), radians(-20.0), 0.0};

const Frame& scene() {
  static const Frame f = test::renderFrame(kPose, kW, kH, kMargin, radians(60.0), PixelFormat::Rgb8, 1, true);
  return f;
}

int maxAbsDiff(const Image& a, const Image& b) {
  int m = 0;
  for (std::size_t i = 0; i < a.bytes().size(); ++i) m = std::max(m, std::abs(a.bytes()[i] - b.bytes()[i]));
  return m;
}

/// The rows of `parity` of the frame's display window.
Image displayRows(const Frame& f, FieldParity parity) {
  Image out(f.displayWidthPx(), fieldRowCount(parity, f.displayHeightPx()), f.image.format());
  for (int r = 0; r < out.heightPx(); ++r) {
    const std::uint8_t* src = f.image.row(f.margin.y + rasterRow(parity, r)) + 3 * f.margin.x;
    std::copy(src, src + out.strideBytes(), out.row(r));
  }
  return out;
}

class EveryWarp : public ::testing::TestWithParam<WarpKind> {};

TEST_P(EveryWarp, IdentityPoseReproducesTheDisplayWindow) {
  auto warp = makeWarp(GetParam(), kW, kH);
  for (FieldParity parity : {FieldParity::Top, FieldParity::Bottom, FieldParity::Progressive}) {
    Image out(kW, fieldRowCount(parity, kH), PixelFormat::Rgb8);
    const WarpResult r = warp->warp(scene(), scene().pose, parity, out);
    ASSERT_EQ(r.status, WarpStatus::Ok);
    EXPECT_EQ(r.marginViolations, 0u);
    EXPECT_FALSE(r.fellBack);
    EXPECT_LE(maxAbsDiff(out, displayRows(scene(), parity)), 1) << toString(GetParam());
    // The sampling map is the identity (plus margin) on the field's rows
    const glm::dvec2 p{37.5, rasterRow(parity, 5) + 0.5};
    const auto src = warp->sourcePx(p);
    ASSERT_TRUE(src.has_value());
    EXPECT_NEAR(src->x, p.x + kMargin.x, 1e-6);
    EXPECT_NEAR(src->y, p.y + kMargin.y, 1e-6);
  }
}

TEST_P(EveryWarp, RejectsBadFramesAndOutputsWithoutTouchingThem) {
  auto warp = makeWarp(GetParam(), kW, kH);
  Image out(kW, kH / 2, PixelFormat::Rgb8);
  EXPECT_EQ(warp->warp(Frame{}, kPose, FieldParity::Top, out).status, WarpStatus::BadFrame);
  Image wrongRows(kW, kH / 2 + 1, PixelFormat::Rgb8);
  EXPECT_EQ(warp->warp(scene(), kPose, FieldParity::Top, wrongRows).status, WarpStatus::BadOutput);
  Image wrongFormat(kW, kH / 2, PixelFormat::Grey8);
  EXPECT_EQ(warp->warp(scene(), kPose, FieldParity::Top, wrongFormat).status, WarpStatus::BadOutput);
}

INSTANTIATE_TEST_SUITE_P(Kinds, EveryWarp,
                         ::testing::Values(WarpKind::Hold, WarpKind::Quadratic, WarpKind::Homography,
                                           WarpKind::Range3d),
                         [](const auto& p) { return std::string(toString(p.param)); });

TEST(FieldRows, EachParityCarriesItsOwnRasterRowsForBothFieldOrders) {
  // A frame whose every display row has its own grey level
  Frame f;
  f.margin = {4, 4};
  f.intrinsics = Intrinsics::fromHorizontalFov(64, 100, radians(50.0)).withMargin(4, 4);
  f.image.resize(72, 108, PixelFormat::Grey8);
  for (int y = 0; y < 108; ++y)
    for (int x = 0; x < 72; ++x) f.image.row(y)[x] = static_cast<std::uint8_t>(y * 2);
  HoldWarp hold(64, 100);
  for (FieldOrder order : {FieldOrder::TopFirst, FieldOrder::BottomFirst}) {
    VirtualClock clock;
    FieldClockConfig cfg;
    cfg.order = order;
    FieldClock fieldClock(clock, cfg, TimePoint{Nanoseconds{1'000'000'000}});
    for (int i = 0; i < 4; ++i) {
      const FieldTick tick = fieldClock.next();
      const bool firstOfFrame = tick.fieldNumber % 2 == 0;
      const FieldParity expected =
          (order == FieldOrder::TopFirst) == firstOfFrame ? FieldParity::Top : FieldParity::Bottom;
      ASSERT_EQ(tick.parity, expected);
      Image out(64, fieldRowCount(tick.parity, 100), PixelFormat::Grey8);
      ASSERT_EQ(hold.warp(f, f.pose, tick.parity, out).status, WarpStatus::Ok);
      ASSERT_EQ(out.heightPx(), 50);
      for (int r = 0; r < 50; ++r) {
        const int rasterY = tick.parity == FieldParity::Top ? 2 * r : 2 * r + 1;
        ASSERT_EQ(out.row(r)[10], (rasterY + 4) * 2) << "field row " << r;
      }
    }
  }
}

TEST(Range3dWarp, WithoutARangeImageFallsBackToTheQuadratic) {
  Frame f = scene();
  f.rangeM.clear();
  Range3dWarp warp(kW, kH);
  Image out(kW, kH, PixelFormat::Rgb8);
  Pose moved = kPose;
  moved.positionM.y += 5.0;
  const WarpResult r = warp.warp(f, moved, FieldParity::Progressive, out);
  EXPECT_EQ(r.status, WarpStatus::Ok);
  EXPECT_TRUE(r.fellBack);
  QuadraticWarp quad(kW, kH);
  Image expected(kW, kH, PixelFormat::Rgb8);
  quad.warp(f, moved, FieldParity::Progressive, expected);
  EXPECT_EQ(out, expected);
}

TEST(Range3dWarp, MapFollowsTheTrueGeometryForATranslation) {
  Range3dWarp warp(kW, kH);
  Pose moved = kPose;
  moved.positionM += glm::dvec3{3.0, 8.0, -4.0};
  Image out(kW, kH / 2, PixelFormat::Rgb8);
  ASSERT_EQ(warp.warp(scene(), moved, FieldParity::Bottom, out).status, WarpStatus::Ok);
  const OutputGeometry g = OutputGeometry::of(scene(), kW, kH);
  double worst = 0.0;
  for (int y = 1; y < kH; y += 6)
    for (int x = 2; x < kW - 2; x += 5) {
      const glm::dvec2 p{x + 0.5, y + 0.5};
      const auto got = warp.sourcePx(p);
      const auto truth = test::trueSourcePx(scene(), moved, g, p);
      ASSERT_TRUE(got && truth);
      worst = std::max(worst, glm::length(*got - *truth));
    }
  EXPECT_LT(worst, 0.6);
  EXPECT_FALSE(warp.sourcePx({10.5, 0.5}).has_value());  // a top-field row: not in the last field
}

TEST(WarpKind, NamesRoundTrip) {
  for (WarpKind k : {WarpKind::Hold, WarpKind::Quadratic, WarpKind::Homography, WarpKind::Range3d}) {
    EXPECT_EQ(warpKindFromString(toString(k)), k);
  }
  EXPECT_FALSE(warpKindFromString("bicubic").has_value());
  EXPECT_THROW(makeWarp(WarpKind::Hold, 1, 10), std::invalid_argument);
}

}  // namespace
}  // namespace fieldcast::warp
