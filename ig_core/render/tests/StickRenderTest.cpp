// Sticks drawn by both renderers: a uniform block and a striped textured block standing on flat
// ground. The fast caster's hits and colours are judged by the reference renderer's, and the
// stripes of the textured stick must appear at the rows their heights project to.
#include "RenderTestUtil.h"

#include <ig_core/MemoryTerrain.h>
#include <ig_core/Renderer.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace fieldcast::core::test {
namespace {

constexpr auto rgb = opaqueRgb;
constexpr std::uint32_t kGround = rgb(70, 120, 60);
constexpr std::uint32_t kRed = rgb(220, 30, 30);
constexpr std::uint32_t kRoof = rgb(20, 20, 20);
constexpr std::uint32_t kBlue = rgb(30, 60, 220);
constexpr std::uint32_t kWhite = rgb(235, 235, 235);
constexpr double kGroundM = 100.0;
constexpr double kStickUnitM = 0.5;

// side² voxels at 2 m, flat at 100 m, 64-voxel tiles, as many levels as fit (far views are drawn
// at coarser levels); place() stands square blocks of sticks on it.
struct FlatGround {
  int side;
  TerrainGeometry g;
  std::vector<std::uint16_t> heightQ;
  std::vector<std::uint32_t> colour, stickId;
  std::shared_ptr<const StickTable> table;

  FlatGround(int sideVox, std::shared_ptr<const StickTable> sticks) : side(sideVox), table(std::move(sticks)) {
    g.widthVox = g.heightVox = side;
    g.spacingM = 2.0;
    g.heightStepM = 0.05;
    g.tileShift = 6;
    g.levels = 0;
    const auto voxels = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
    heightQ.assign(voxels, static_cast<std::uint16_t>(kGroundM / g.heightStepM));
    colour.assign(voxels, kGround);
    stickId.assign(voxels, 0);
  }
  /// Stick `id` on voxels (i0 .. i0 + n − 1, j0 .. j0 + n − 1), `heightM` tall.
  void place(int i0, int j0, int n, double heightM, std::uint32_t id) {
    for (int j = j0; j < j0 + n; ++j)
      for (int i = i0; i < i0 + n; ++i) {
        const auto k = static_cast<std::size_t>(j * side + i);
        heightQ[k] = static_cast<std::uint16_t>((kGroundM + heightM) / g.heightStepM);
        colour[k] = table->texels(id, 0)[0];  // the top's colour, as a builder writes it
        stickId[k] = id;
      }
  }
  std::unique_ptr<MemoryTerrain> terrain() {
    return std::make_unique<MemoryTerrain>(g, heightQ, colour, stickId, table);
  }
};

// 256² voxels. A uniform red block of 8 × 8 voxels, 8 m tall, at voxels (100..107, 120..127) —
// world x 200..214, y 240..254; and a textured block of 6 × 6 voxels, 12 m tall, at
// (140..145, 120..125): a black roof texel (0.5 m), then 1 m stripes, blue then white, down to the
// ground.
std::unique_ptr<MemoryTerrain> blocks() {
  std::vector<std::uint32_t> striped{kRoof};
  for (int k = 0; k < 23; ++k) striped.push_back((k / 2) % 2 == 0 ? kBlue : kWhite);
  FlatGround ground(256, std::make_shared<const StickTable>(
                             kStickUnitM, std::vector<StickEntry>{{StickKind::Uniform, 16, {kRed}},
                                                                  {StickKind::Textured, 24, striped}}));
  ground.place(100, 120, 8, 8.0, 1);
  ground.place(140, 120, 6, 12.0, 2);
  return ground.terrain();
}

struct StickView {
  const char* name;
  double x, y, altitudeM, headingDeg, pitchDeg;
};

// The blocks seen from the south, low and level; from the south-west, oblique; from above; and far
// off, where coarse levels draw them.
const StickView kViews[] = {
    {"side", 245.0, 150.0, 6.0, 0.0, 0.0},
    {"oblique", 150.0, 160.0, 60.0, 35.0, -25.0},
    {"down", 240.0, 250.0, 150.0, 0.0, -89.0},
    {"far", 245.0, -100.0, 40.0, 0.0, -5.0},
};

TEST(StickRender, TheCasterDrawsSticksAsTheReferenceDoes) {
  const auto terrain = blocks();
  const TerrainView& view = terrain->view();
  RenderSettings settings;
  settings.rangeImage = true;
  settings.hazeRangeM = 0.0;  // colours compared as they are
  Renderer renderer(view, settings, 2);
  const ReferenceRenderer reference(view);
  for (const StickView& s : kViews) {
    ViewRequest request;
    request.pose.positionM = {s.x, s.y, kGroundM + s.altitudeM};
    request.pose.headingRad = radians(s.headingDeg);
    request.pose.pitchRad = radians(s.pitchDeg);
    request.display = Intrinsics::fromHorizontalFov(160, 120, radians(50.0));
    const Frame fast = renderer.render(request);
    const Frame ref = reference.render(request, settings);
    const HitAgreement hits = compareHits(fast, ref, view.geometry(), settings);
    // Colours: pixels whose colour differs from the reference's by more than a third of the range
    const int differ = pixelsDiffering(fast, ref, 80);
    const int pixels = fast.image.widthPx() * fast.image.heightPx();
    const int red = pixelsNear(fast, kRed, 30), redRef = pixelsNear(ref, kRed, 30);
    const int stripes = pixelsNear(fast, kBlue, 30) + pixelsNear(fast, kWhite, 30);
    std::printf("%-8s hits %.4f same; colours: %d of %d differ; red %d (reference %d), stripes %d\n", s.name,
                hits.fraction(), differ, pixels, red, redRef, stripes);
    EXPECT_GE(hits.fraction(), 0.995) << s.name;
    EXPECT_LE(differ, pixels / 100) << s.name;
    EXPECT_GT(red, 20) << s.name << ": the uniform block is not drawn";
    EXPECT_NEAR(red, redRef, std::max(10, redRef / 10)) << s.name;
    EXPECT_GT(stripes, 20) << s.name << ": the textured block's sides are not drawn";
  }
}

// 128² voxels and a slim uniform red tower of 2 × 2 voxels, 20 m tall, at voxels (64..65, 64..65):
// world x, y 128..130.
std::unique_ptr<MemoryTerrain> tower() {
  FlatGround ground(
      128, std::make_shared<const StickTable>(kStickUnitM, std::vector<StickEntry>{{StickKind::Uniform, 40, {kRed}}}));
  ground.place(64, 64, 2, 20.0, 1);
  return ground.terrain();
}

// The tower looked down on steeply from 14 m above its top and 8 m beside it, left and right of the
// view's centre, facing every way. The planes of the columns beside the centre lean (by 20-30°),
// and the tower rises above the lines where they meet the ground past the crossings the march takes
// there; near the nadir their rays run back toward the camera's foot, against the march, so the
// march alone gave the rows that see the tower's top the ground (RENDERER.md, "Steep terrain in a
// tilted column plane"): it drew 62-76% of the reference's red pixels, 98.8-99.1% of all pixels on
// the reference's voxel or a neighbour (now 93-101%, 99.8% and more).
// The one-column march and the lane march, and the one-column march with two sub-rows a pixel
// (the rows cast again are whole pixels).
struct MarchKind {
  bool laneMarch;
  int subRows;
};
class TowerBesideASteepView : public ::testing::TestWithParam<MarchKind> {};

TEST_P(TowerBesideASteepView, IsNotPassedOver) {
  const auto terrain = tower();
  const TerrainView& view = terrain->view();
  RenderSettings settings;
  settings.rangeImage = true;
  settings.hazeRangeM = 0.0;
  settings.laneMarch = GetParam().laneMarch;
  settings.verticalSupersample = GetParam().subRows;
  Renderer renderer(view, settings, 2);
  const ReferenceRenderer reference(view);
  for (const double headingDeg : {0.0, 90.0, 200.0, 300.0}) {
    for (const double besideDeg : {-25.0, 25.0}) {
      const double bearing = radians(headingDeg + besideDeg + 180.0);  // from the tower to the camera
      ViewRequest request;
      request.pose.positionM = {129.0 + 8.0 * std::sin(bearing), 129.0 + 8.0 * std::cos(bearing), kGroundM + 34.0};
      request.pose.headingRad = radians(headingDeg);
      request.pose.pitchRad = radians(-75.0);
      request.display = Intrinsics::fromHorizontalFov(160, 120, radians(70.0));
      const Frame fast = renderer.render(request);
      const Frame ref = reference.render(request, settings);
      const HitAgreement hits = compareHits(fast, ref, view.geometry(), settings);
      const int red = pixelsNear(fast, kRed, 30), redRef = pixelsNear(ref, kRed, 30);
      std::printf("heading %5.1f, tower %+5.1f°: hits %.4f same; red %d (reference %d)\n", headingDeg, besideDeg,
                  hits.fraction(), red, redRef);
      EXPECT_GT(redRef, 300) << "the tower is not in view";
      EXPECT_NEAR(red, redRef, redRef / 10) << "heading " << headingDeg << ", tower " << besideDeg;
      EXPECT_GE(hits.fraction(), 0.995) << "heading " << headingDeg << ", tower " << besideDeg;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(StickRender, TowerBesideASteepView,
                         ::testing::Values(MarchKind{false, 1}, MarchKind{true, 1}, MarchKind{false, 2}),
                         [](const ::testing::TestParamInfo<MarchKind>& kind) {
                           return std::string(kind.param.laneMarch ? "LaneMarch" : "ColumnMarch") +
                                  (kind.param.subRows > 1 ? "TwoSubRows" : "");
                         });

// 256² voxels: a wood of slim red trees, 1 × 1 voxel and 16 m tall, every 4 voxels each way.
std::unique_ptr<MemoryTerrain> wood() {
  FlatGround ground(
      256, std::make_shared<const StickTable>(kStickUnitM, std::vector<StickEntry>{{StickKind::Uniform, 32, {kRed}}}));
  for (int j = 2; j < 256; j += 4)
    for (int i = 2; i < 256; i += 4) ground.place(i, j, 1, 16.0, 1);
  return ground.terrain();
}

// The march looks past its crossings where a voxel spans as large a share of the frame's width as
// 8 pixels of an 864-pixel-wide frame (lookPastVoxelPx), so the rows it casts again are about the
// same share of a wide frame's pixels as of a narrow one's, and the looks cost a wide frame no more
// per pixel (17.9% and 17.7% here). With 8 pixels at every width the 2304-pixel-wide frame cast
// 32.1% of its pixels again, and the bench's 2304-wide down view took 3.4× as long.
TEST(StickRender, TheRowsCastAgainAreTheSameShareOfAWideFrame) {
  const auto terrain = wood();
  RenderSettings settings;
  settings.hazeRangeM = 0.0;
  Renderer renderer(terrain->view(), settings, 2);
  ViewRequest request;
  request.pose.positionM = {256.0, 60.0, kGroundM + 120.0};
  request.pose.headingRad = radians(20.0);
  request.pose.pitchRad = radians(-55.0);
  double share[2] = {};
  for (int wide = 0; wide < 2; ++wide) {
    request.display = wide ? Intrinsics::fromHorizontalFov(1920, 1080, radians(70.0))
                           : Intrinsics::fromHorizontalFov(720, 405, radians(70.0));
    RenderStats stats;
    const Frame frame = renderer.render(request, &stats);
    const double pixels = static_cast<double>(frame.image.widthPx()) * frame.image.heightPx();
    share[wide] = (static_cast<double>(stats.rays) - pixels) / pixels;
    std::printf("%d px wide: %.2f%% of the pixels cast again\n", frame.image.widthPx(), 100.0 * share[wide]);
  }
  EXPECT_GT(share[0], 0.001) << "the view does not look past any crossing";
  EXPECT_LT(share[1], 1.5 * share[0] + 0.002);
}

TEST(StickRender, ATexturedSticksStripesLieAtTheirHeights) {
  const auto terrain = blocks();
  RenderSettings settings;
  settings.hazeRangeM = 0.0;
  Renderer renderer(terrain->view(), settings, 1);
  // Level, looking north at the textured block's south face from 60 m, eye 6 m up
  ViewRequest request;
  request.pose.positionM = {285.0, 180.0, kGroundM + 6.0};
  request.display = Intrinsics::fromHorizontalFov(200, 400, radians(30.0));
  const Frame frame = renderer.render(request);
  const Intrinsics& k = frame.intrinsics;
  const int u = static_cast<int>(k.cxPx);
  // Down the centre column: each change between blue and white is a stripe edge
  const auto channel = [&](int v, int c) { return static_cast<int>(frame.image.row(v)[3 * u + c]); };
  const auto isBlue = [&](int v) { return channel(v, 2) > 150 && channel(v, 0) < 100; };
  const auto isWhite = [&](int v) { return channel(v, 0) > 180 && channel(v, 2) > 180; };
  std::vector<int> edges;
  for (int v = 1; v < k.heightPx; ++v) {
    if ((isBlue(v - 1) && isWhite(v)) || (isWhite(v - 1) && isBlue(v))) edges.push_back(v);
  }
  // Texel s of the stick lies s·0.5 m below its 12 m top; blue and white change at s = 3, 5, … 23:
  // at heights z = 11.5 − n m, n = 1 … 11. The face is the surface's lean from the ground voxel's
  // centre line (y 238) to the block's first (y 240): a point at height z lies at y = 238 + 2·z/12.
  ASSERT_EQ(edges.size(), 11u) << "the textured block's face does not show its 11 stripe edges";
  for (std::size_t n = 1; n <= edges.size(); ++n) {
    const double z = 11.5 - static_cast<double>(n);
    const double depth = 238.0 + 2.0 * z / 12.0 - request.pose.positionM.y;
    const double row = k.cyPx - k.fyPx * (kGroundM + z - request.pose.positionM.z) / depth;
    EXPECT_NEAR(edges[n - 1], row, 1.0) << "stripe edge " << n << " (" << z << " m up)";
  }
}

}  // namespace
}  // namespace fieldcast::core::test
