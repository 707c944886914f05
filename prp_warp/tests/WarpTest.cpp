// The warps through their common interface: identity, field rows and parity, fallbacks, bad input.
#include "AnalyticScene.h"

#include <prp_warp/FieldClock.h>
#include <prp_warp/Warps.h>

#include <gtest/gtest.h>
#include <glm/mat2x2.hpp>

#include <cstdio>

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
                         ::testing::Values(WarpKind::Hold, WarpKind::Rotation, WarpKind::Quadratic,
                                           WarpKind::Homography, WarpKind::Mesh, WarpKind::Range3d),
                         [](const auto& p) { return std::string(toString(p.param)); });

// A frame for a display rolled `rollDeg`, as ig_core lays one out: 60 px margins (room for the
// turned window), and the footprint the renderer draws — the window grown by 16 / 12 px, turned.
Frame rolledFrame(double rollDeg = 20.0) {
  Frame f = test::renderFrame(kPose, kW, kH, MarginPx{60, 60}, radians(60.0), PixelFormat::Rgb8, 1, true);
  FrameFootprint& fp = f.footprint;
  fp.whole = false;
  fp.cosRoll = std::cos(radians(rollDeg));
  fp.sinRoll = std::sin(radians(rollDeg));
  fp.cxPx = f.intrinsics.cxPx;
  fp.cyPx = f.intrinsics.cyPx;
  fp.fxPx = f.intrinsics.fxPx;
  fp.fyPx = f.intrinsics.fyPx;
  fp.xMin = (-kW / 2.0 - 16) / fp.fxPx;
  fp.xMax = (kW / 2.0 + 16) / fp.fxPx;
  fp.yMin = (-kH / 2.0 - 12) / fp.fyPx;
  fp.yMax = (kH / 2.0 + 12) / fp.fyPx;
  fp.widthPx = f.intrinsics.widthPx;
  fp.heightPx = f.intrinsics.heightPx;
  return f;
}

class PoseWarp : public ::testing::TestWithParam<WarpKind> {};

TEST_P(PoseWarp, ARolledFramesViolationsAreTheSamplesOutsideItsFootprint) {
  const Frame frame = rolledFrame();
  auto warp = makeWarp(GetParam(), kW, kH);
  Image out(kW, kH / 2, PixelFormat::Rgb8);
  Pose pose = frame.pose;
  pose.rollRad = radians(20.0);  // the roll the frame was laid out for: inside its footprint
  ASSERT_EQ(warp->warp(frame, pose, FieldParity::Top, out).status, WarpStatus::Ok);
  EXPECT_EQ(warp->warp(frame, pose, FieldParity::Top, out).marginViolations, 0u);
  // 25° further: the window's corners leave the footprint, though not the frame
  pose.rollRad = radians(45.0);
  for (const FieldParity parity : {FieldParity::Top, FieldParity::Bottom}) {
    const WarpResult r = warp->warp(frame, pose, parity, out);
    ASSERT_EQ(r.status, WarpStatus::Ok);
    std::uint32_t outsideFootprint = 0, outsideFrame = 0;
    for (int row = 0; row < kH / 2; ++row) {
      for (int i = 0; i < kW; ++i) {
        const std::optional<glm::dvec2> p = warp->sourcePx({i + 0.5, rasterRow(parity, row) + 0.5});
        ASSERT_TRUE(p.has_value());
        outsideFootprint += frame.footprint.contains(*p) ? 0 : 1;
        outsideFrame +=
            p->x >= 0 && p->x <= frame.intrinsics.widthPx && p->y >= 0 && p->y <= frame.intrinsics.heightPx ? 0 : 1;
      }
    }
    EXPECT_EQ(outsideFrame, 0u);
    EXPECT_GT(outsideFootprint, 200u);
    // Rows taken as straight between their inside ends: within a pixel a row of the count by point
    EXPECT_NEAR(static_cast<double>(r.marginViolations), outsideFootprint, kH / 2.0) << toString(GetParam());
  }
  // The same frame without its footprint counts only what falls outside the frame: nothing
  Frame whole = frame;
  whole.footprint = FrameFootprint{};
  EXPECT_EQ(warp->warp(whole, pose, FieldParity::Top, out).marginViolations, 0u);
}

// What the renderer leaves out of a rolled frame is never read: with every pixel outside its
// columns' runs (FrameFootprint::rows) overwritten, a field warped anywhere the margins allow is
// the same, to the bit. The rolls that come nearest the footprint's edge without leaving it test
// the runs' ends against the real sampler.
TEST_P(PoseWarp, AFieldWithinTheMarginsReadsOnlyTheFootprintsRows) {
  const Frame frame = rolledFrame();
  Frame hidden = frame;
  for (int u = 0; u < hidden.intrinsics.widthPx; ++u) {
    const RowRun run = hidden.footprint.rows(u);
    for (int v = 0; v < hidden.intrinsics.heightPx; ++v) {
      if (v >= run.first && v < run.end) continue;
      std::uint8_t* px = hidden.image.row(v) + 3 * u;
      px[0] = 255, px[1] = 0, px[2] = 255;
      hidden.rangeM[static_cast<std::size_t>(v * hidden.intrinsics.widthPx + u)] = 1.0f;
    }
  }
  auto warp = makeWarp(GetParam(), kW, kH);
  int compared = 0;
  int fields = 0;
  for (double rollDeg = -5.0; rollDeg <= 45.0; rollDeg += 0.5) {
    Pose pose = frame.pose;
    pose.rollRad = radians(rollDeg);
    for (const FieldParity parity : {FieldParity::Top, FieldParity::Bottom}) {
      ++fields;
      Image shown(kW, kH / 2, PixelFormat::Rgb8), fromHidden(kW, kH / 2, PixelFormat::Rgb8);
      const WarpResult r = warp->warp(frame, pose, parity, shown);
      if (r.marginViolations != 0) continue;
      ASSERT_EQ(warp->warp(hidden, pose, parity, fromHidden).marginViolations, 0u);
      EXPECT_TRUE(shown == fromHidden) << toString(GetParam()) << " at " << rollDeg << "°";
      ++compared;
    }
  }
  std::printf("%s: %d of %d fields within the margins\n", std::string(toString(GetParam())).c_str(), compared, fields);
  EXPECT_GT(compared, 10);
  EXPECT_LT(compared, fields - 10);  // and some rolls leave them
}

// A warp whose map is a given affine one, its rows bent into parabolas (`bend` px per px² from
// the raster's middle column, down the frame), and which writes nothing: the footprint count alone.
class BentAffineWarp final : public Warp {
 public:
  BentAffineWarp(glm::dmat2 a, glm::dvec2 b, double bend) : Warp(kW, kH), mA(a), mB(b), mBend(bend) {}
  WarpKind kind() const noexcept override { return WarpKind::Rotation; }
  std::optional<glm::dvec2> sourcePx(glm::dvec2 rasterPx) const noexcept override {
    const double x = rasterPx.x - kW / 2.0;
    return mA * rasterPx + mB + glm::dvec2{0.0, mBend * x * x};
  }

 private:
  WarpResult doWarp(const Frame&, const Image&, const Pose&, FieldParity, FieldRows) noexcept override { return {}; }
  glm::dmat2 mA;
  glm::dvec2 mB;
  double mBend;
};

// The count is exact for rows that leave the footprint at one end, at both, that keep only a few
// pixels at an end, or none, and for bent rows that leave it between two inside ends (around the
// middle); but for a row whose ends and middle are outside and whose inside run is shorter than
// the 16-pixel comb that looks for it (counted all outside).
TEST(FootprintCount, CountsTheSamplesOutsideRowByRow) {
  Frame frame = rolledFrame();
  const glm::dvec2 centre{frame.intrinsics.cxPx, frame.intrinsics.cyPx};
  Image out(kW, kH / 2, PixelFormat::Rgb8);
  int rowsWithMiddleOnlyOut = 0, exact = 0, maps = 0;
  // Checks one map against the count pixel by pixel
  const auto check = [&](const glm::dmat2& a, glm::dvec2 shift, double bend) {
    BentAffineWarp warp(a, centre + shift - a * glm::dvec2{kW / 2.0, kH / 2.0}, bend);
    std::uint32_t truth = 0, missable = 0;
    for (int row = 0; row < kH / 2; ++row) {
      const double y = rasterRow(FieldParity::Bottom, row) + 0.5;
      const auto inside = [&](double x) { return frame.footprint.contains(*warp.sourcePx({x, y})); };
      int outside = 0;
      for (int i = 0; i < kW; ++i) outside += inside(i + 0.5) ? 0 : 1;
      truth += static_cast<std::uint32_t>(outside);
      const bool middle = inside(kW / 2 + 0.5);
      const bool left = inside(0.5), right = inside(kW - 0.5);
      rowsWithMiddleOnlyOut += left && right && !middle ? 1 : 0;
      if (kW - outside < 16 && !left && !middle && !right) missable += static_cast<std::uint32_t>(kW - outside);
    }
    const std::uint32_t counted = warp.warp(frame, frame.pose, FieldParity::Bottom, out).marginViolations;
    EXPECT_GE(counted, truth) << "shift " << shift.x << "," << shift.y << " bend " << bend;
    EXPECT_LE(counted, truth + missable) << "shift " << shift.x << "," << shift.y << " bend " << bend;
    exact += counted == truth ? 1 : 0;
    ++maps;
  };
  // Straight rows (an affine map: turned and scaled about the frame's centre, then shifted)
  for (const double turnDeg : {0.0, 20.0, 35.0, 50.0, 90.0, 160.0}) {
    for (const double scale : {0.6, 1.0, 1.6}) {
      for (const glm::dvec2 shift : {glm::dvec2{0, 0}, glm::dvec2{70, -40}, glm::dvec2{-95, 30}, glm::dvec2{120, 0}}) {
        const double t = radians(turnDeg);
        check(scale * glm::dmat2{std::cos(t), std::sin(t), -std::sin(t), std::cos(t)}, shift, 0.0);
      }
    }
  }
  // Rows bent up in the middle across the top edge of a footprint not turned: out between two
  // inside ends
  frame = rolledFrame(0.0);
  for (const double up : {40.0, 50.0, 60.0}) check(glm::dmat2{1.0}, {0.0, -up}, 0.004);
  std::printf("%d of %d maps counted exactly; %d rows out only between two inside ends\n", exact, maps,
              rowsWithMiddleOnlyOut);
  EXPECT_GT(rowsWithMiddleOnlyOut, 0);
  EXPECT_GT(exact, maps / 2);
}

INSTANTIATE_TEST_SUITE_P(Kinds, PoseWarp,
                         ::testing::Values(WarpKind::Rotation, WarpKind::Quadratic, WarpKind::Homography,
                                           WarpKind::Mesh, WarpKind::Range3d),
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

class RangeWarp : public ::testing::TestWithParam<WarpKind> {};

TEST_P(RangeWarp, WithoutARangeImageFallsBackToTheQuadratic) {
  Frame f = scene();
  f.rangeM.clear();
  auto warp = makeWarp(GetParam(), kW, kH);
  Image out(kW, kH, PixelFormat::Rgb8);
  Pose moved = kPose;
  moved.positionM.y += 5.0;
  const WarpResult r = warp->warp(f, moved, FieldParity::Progressive, out);
  EXPECT_EQ(r.status, WarpStatus::Ok);
  EXPECT_TRUE(r.fellBack);
  EXPECT_EQ(r.fallbackReason, FallbackReason::NoRange);
  QuadraticWarp quad(kW, kH);
  Image expected(kW, kH, PixelFormat::Rgb8);
  quad.warp(f, moved, FieldParity::Progressive, expected);
  EXPECT_EQ(out, expected);
}

INSTANTIATE_TEST_SUITE_P(Kinds, RangeWarp, ::testing::Values(WarpKind::Range3d, WarpKind::Mesh),
                         [](const auto& p) { return std::string(toString(p.param)); });

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

// A field pitched up past the frame's top: its first rows get no splat. They continue the first
// row below that has one, upwards (sources above the frame's top, counted as violations and
// sampled at the top edge), as empty rows lower down continue the row above them. They were left
// without a sample: sampled at the frame's top-left pixel (and counted as violations, as NaN is).
TEST(Range3dWarp, EmptyRowsAtTheFieldsTopContinueTheFirstRowBelow) {
  Range3dWarp warp(kW, kH);
  Pose up = kPose;
  up.pitchRad += radians(15.0);
  Image out(kW, kH / 2, PixelFormat::Rgb8);
  const WarpResult r = warp.warp(scene(), up, FieldParity::Top, out);
  ASSERT_EQ(r.status, WarpStatus::Ok);
  const auto top = warp.sourcePx({kW / 2 + 0.5, 0.5});
  ASSERT_TRUE(top.has_value()) << "the field's first row has no sample";
  EXPECT_LT(top->y, 0.0);  // above the frame
  int firstInside = -1;    // the first raster row (of this field) whose source lies in the frame
  for (int y = 0; y < kH && firstInside < 0; y += 2) {
    const auto p = warp.sourcePx({kW / 2 + 0.5, y + 0.5});
    ASSERT_TRUE(p.has_value()) << "row " << y;
    if (p->y >= 0.0) firstInside = y;
  }
  ASSERT_GT(firstInside, 2);  // the case at hand: several rows see above the frame
  // Rows above it lie above the frame, one above the other as the raster's rows are
  for (int y = 0; y + 2 < firstInside; y += 2) {
    EXPECT_LT(warp.sourcePx({kW / 2 + 0.5, y + 0.5})->y, warp.sourcePx({kW / 2 + 0.5, y + 2.5})->y) << "row " << y;
  }
  EXPECT_GE(r.marginViolations, static_cast<std::uint32_t>(kW * (firstInside / 2)));
  // Sampled at the frame's top edge below each source, not at its top-left pixel
  const std::uint8_t* edge = scene().image.row(0) + 3 * static_cast<int>(top->x);
  const std::uint8_t* got = out.row(0) + 3 * (kW / 2);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], edge[c], 24) << c;
}

/// The worst distance between the mesh warp's map and the truth over raster points every 5 px
/// (every row: the map is defined on the whole raster), below raster row `fromRow`.
double worstMapError(const MeshWarp& warp, const Pose& fieldPose, int fromRow) {
  const OutputGeometry g = OutputGeometry::of(scene(), kW, kH);
  double worst = 0.0;
  for (int y = fromRow; y < kH; y += 5)
    for (int x = 2; x < kW - 2; x += 5) {
      const glm::dvec2 p{x + 0.5, y + 0.5};
      const auto got = warp.sourcePx(p);
      const auto truth = test::trueSourcePx(scene(), fieldPose, g, p);
      if (!got || !truth) return std::numeric_limits<double>::infinity();
      worst = std::max(worst, glm::length(*got - *truth));
    }
  return worst;
}

// A translation big enough that the ground below zooms by ~1.25 (a Newton step, not the
// rotation-only step, is what converges there), the horizon in the top cell row.
const Pose kTranslated{kPose.positionM + glm::dvec3{20.0, 60.0, -40.0}, kPose.headingRad, kPose.pitchRad, 0.0};

TEST(MeshWarp, NodesLandExactlyAndTheMapFollowsTheTrueGeometryForATranslation) {
  MeshWarp warp(kW, kH);
  Image out(kW, kH / 2, PixelFormat::Rgb8);
  ASSERT_EQ(warp.warp(scene(), kTranslated, FieldParity::Bottom, out).status, WarpStatus::Ok);
  EXPECT_EQ(warp.lastUnsolvedNodes(), 0);
  EXPECT_EQ(warp.lastMap().refinedCells(), 0);  // refinement is off by default
  // At the nodes the map is the truth, to the solver's tolerance (plus the range image's
  // interpolation between pixels)
  const OutputGeometry g = OutputGeometry::of(scene(), kW, kH);
  const MeshMap& mesh = warp.lastMap();
  double worstNode = 0.0;
  for (int l = 0; l < mesh.rows(); ++l)
    for (int k = 0; k < mesh.columns(); ++k) {
      const glm::dvec2 q{static_cast<double>(mesh.nodeXPx(k)), static_cast<double>(mesh.nodeYPx(l))};
      const auto truth = test::trueSourcePx(scene(), kTranslated, g, q);
      ASSERT_TRUE(truth);
      worstNode = std::max(worstNode, glm::length(glm::dvec2{mesh.frameX(k, l), mesh.frameY(k, l)} - *truth));
    }
  EXPECT_LT(worstNode, 0.06);
  // Between the nodes, below the cell row that holds the horizon: bilinear is close
  EXPECT_LT(worstMapError(warp, kTranslated, 16), 0.3);
  // In that row the parallax falls off as 1/range towards the horizon: bilinear misses by a pixel
  EXPECT_GT(worstMapError(warp, kTranslated, 0), 0.8);
}

TEST(MeshWarp, RefiningTheCellsBilinearMissesFollowsTheHorizon) {
  MeshWarp warp(kW, kH, ResampleKernel::Fast, MeshOptions{16, 0.25});
  Image out(kW, kH / 2, PixelFormat::Rgb8);
  ASSERT_EQ(warp.warp(scene(), kTranslated, FieldParity::Bottom, out).status, WarpStatus::Ok);
  const int cells = (warp.lastMap().columns() - 1) * (warp.lastMap().rows() - 1);
  EXPECT_GT(warp.lastMap().refinedCells(), 0);
  EXPECT_LT(warp.lastMap().refinedCells(), cells / 4);  // only where it is needed
  EXPECT_LT(worstMapError(warp, kTranslated, 0), 0.3);
  // The fast kernel follows the refined map like the reference
  MeshWarp reference(kW, kH, ResampleKernel::Reference, MeshOptions{16, 0.25});
  Image expected(kW, kH / 2, PixelFormat::Rgb8);
  reference.warp(scene(), kTranslated, FieldParity::Bottom, expected);
  EXPECT_LE(maxAbsDiff(out, expected), 1);
}

TEST(RotationWarp, IsExactForATurnAndBlindToATranslation) {
  RotationWarp warp(kW, kH);
  const OutputGeometry g = OutputGeometry::of(scene(), kW, kH);
  Image out(kW, kH, PixelFormat::Rgb8);
  Pose turned = kPose;
  turned.headingRad += radians(4.0);
  turned.rollRad = radians(10.0);
  ASSERT_EQ(warp.warp(scene(), turned, FieldParity::Progressive, out).status, WarpStatus::Ok);
  const glm::dvec2 p{80.5, 70.5};
  EXPECT_NEAR(glm::length(*warp.sourcePx(p) - *test::trueSourcePx(scene(), turned, g, p)), 0.0, 1e-6);
  // A move sideways: the ground shifts in the truth, not in the rotation-only map
  Pose moved = kPose;
  moved.positionM.x += 20.0;
  warp.warp(scene(), moved, FieldParity::Progressive, out);
  EXPECT_NEAR(glm::length(*warp.sourcePx(p) - g.framePxOf(p)), 0.0, 1e-6);
  EXPECT_GT(glm::length(*test::trueSourcePx(scene(), moved, g, p) - g.framePxOf(p)), 3.0);
}

TEST(WarpKind, NamesRoundTrip) {
  for (WarpKind k : {WarpKind::Hold, WarpKind::Rotation, WarpKind::Quadratic, WarpKind::Homography, WarpKind::Mesh,
                     WarpKind::Range3d}) {
    EXPECT_EQ(warpKindFromString(toString(k)), k);
  }
  EXPECT_FALSE(warpKindFromString("bicubic").has_value());
  EXPECT_THROW(makeWarp(WarpKind::Hold, 1, 10), std::invalid_argument);
}

}  // namespace
}  // namespace fieldcast::warp
