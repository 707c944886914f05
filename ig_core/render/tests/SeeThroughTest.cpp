// Complex sticks drawn by both renderers: a red deck on a cavity (a bridge, a table) and a block
// of half-transparent glass, in front of a blue wall. Through the cavity and the glass the rays go
// on as secondary rays; far away the cavities are filled and no ray goes through.
#include "ColumnCaster.h"
#include "RenderTestUtil.h"
#include "SeeThrough.h"
#include "TileWindows.h"

#include <ig_core/MemoryTerrain.h>
#include <ig_core/Renderer.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace fieldcast::core::test {
namespace {

constexpr auto rgb = opaqueRgb;
constexpr std::uint32_t kGround = rgb(70, 120, 60);
constexpr std::uint32_t kRed = rgb(220, 30, 30);
constexpr std::uint32_t kBlue = rgb(30, 60, 220);
constexpr std::uint32_t kCavity = 0u;
constexpr std::uint32_t kGlass = (rgb(240, 240, 40) & 0x00FFFFFFu) | 0x80000000u;  // yellow, alpha 128
constexpr double kGroundM = 100.0;

// 256² voxels at 2 m, flat at 100 m, 64-voxel tiles. A deck of 8 × 8 voxels at (100..107,
// 120..127) — world x 200..214, y 240..254 —, 6 m tall: 1 m of red over a 5 m cavity. A glass
// pane of 6 × 1 at (140..145, 120), 8 m, every texel half transparent. A blue wall 20 m
// tall along y 300..302 (voxels 60..199, 150..151) behind both. The ground may slope, rising
// `riseX` and `riseY` metres a voxel east and north from `groundM` at voxel (0, 0).
std::unique_ptr<MemoryTerrain> deckAndGlass(double groundM = kGroundM, double riseX = 0.0, double riseY = 0.0) {
  constexpr int kSide = 256;
  TerrainGeometry g;
  g.widthVox = g.heightVox = kSide;
  g.spacingM = 2.0;
  g.heightStepM = 0.05;
  g.tileShift = 6;
  g.levels = 0;  // as many as fit: 256, 128, 64
  const auto groundQ = [&](int i, int j, double aboveM) {
    return static_cast<std::uint16_t>(std::lround((groundM + riseX * i + riseY * j + aboveM) / g.heightStepM));
  };
  std::vector<std::uint16_t> heightQ(kSide * kSide);
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) heightQ[static_cast<std::size_t>(j * kSide + i)] = groundQ(i, j, 0.0);
  std::vector<std::uint32_t> colour(kSide * kSide, kGround);
  std::vector<std::uint32_t> stickId(kSide * kSide, 0);
  std::vector<std::uint32_t> deck{kRed, kRed};
  deck.resize(12, kCavity);
  auto table = std::make_shared<const StickTable>(
      0.5, std::vector<StickEntry>{{StickKind::Complex, 12, deck},
                                   {StickKind::Complex, 16, std::vector<std::uint32_t>(16, kGlass)},
                                   {StickKind::Uniform, 40, {kBlue}}});
  const auto place = [&](int i0, int j0, int w, int h, double heightM, std::uint32_t id) {
    for (int j = j0; j < j0 + h; ++j)
      for (int i = i0; i < i0 + w; ++i) {
        const auto k = static_cast<std::size_t>(j * kSide + i);
        heightQ[k] = groundQ(i, j, heightM);
        stickId[k] = id;  // the voxel's colour stays the ground's: what shows below a complex stick
      }
  };
  place(100, 120, 8, 8, 6.0, 1);
  place(140, 120, 6, 1, 8.0, 2);
  place(60, 150, 140, 2, 20.0, 3);
  return std::make_unique<MemoryTerrain>(g, heightQ, colour, stickId, std::move(table));
}

// Half the glass's yellow over the wall's blue (the wall is what the glass is seen against)
constexpr std::uint32_t kGlassOverBlue = rgb((240 + 30) / 2, (240 + 60) / 2, (40 + 220) / 2);

struct DeckView {
  const char* name;
  double x, y, altitudeM, headingDeg, pitchDeg;
  int widthPx, heightPx;
  double hfovDeg = 50.0;
};

const DeckView kViews[] = {
    {"under", 240.0, 170.0, 2.5, 0.0, 2.0, 160, 120, 90.0},  // level, low: under the deck, the glass
    {"oblique", 170.0, 180.0, 20.0, 35.0, -15.0, 160, 120},  // from the south-west, above
    {"down", 245.0, 250.0, 60.0, 0.0, -70.0, 160, 120},      // steeply down past the deck's edge
};

ViewRequest requestFor(const DeckView& s) {
  ViewRequest request;
  request.pose.positionM = {s.x, s.y, kGroundM + s.altitudeM};
  request.pose.headingRad = radians(s.headingDeg);
  request.pose.pitchRad = radians(s.pitchDeg);
  request.display = Intrinsics::fromHorizontalFov(s.widthPx, s.heightPx, radians(s.hfovDeg));
  return request;
}

TEST(SeeThrough, TheCasterSeesThroughCavitiesAndGlassAsTheReferenceDoes) {
  const auto terrain = deckAndGlass();
  const TerrainView& view = terrain->view();
  RenderSettings settings;
  settings.rangeImage = true;
  settings.hazeRangeM = 0.0;  // colours compared as they are
  Renderer renderer(view, settings, 2);
  const ReferenceRenderer reference(view);
  for (const DeckView& s : kViews) {
    const ViewRequest request = requestFor(s);
    RenderStats stats;
    const Frame fast = renderer.render(request, &stats);
    const Frame ref = reference.render(request, settings);
    if (const char* dump = std::getenv("SEE_THROUGH_DUMP")) {
      for (const auto& [f, tag] : {std::pair{&fast, "fast"}, std::pair{&ref, "ref"}}) {
        const std::string path = std::string(dump) + "/" + s.name + "-" + tag + ".ppm";
        FILE* out = std::fopen(path.c_str(), "wb");
        std::fprintf(out, "P6 %d %d 255\n", f->image.widthPx(), f->image.heightPx());
        for (int v = 0; v < f->image.heightPx(); ++v) std::fwrite(f->image.row(v), 3, f->image.widthPx(), out);
        std::fclose(out);
      }
    }
    const HitAgreement hits = compareHits(fast, ref, view.geometry(), settings);
    const int differ = pixelsDiffering(fast, ref, 40);
    const int pixels = fast.image.widthPx() * fast.image.heightPx();
    const int blue = pixelsNear(fast, kBlue, 30), blueRef = pixelsNear(ref, kBlue, 30);
    const int glass = pixelsNear(fast, kGlassOverBlue, 30), glassRef = pixelsNear(ref, kGlassOverBlue, 30);
    std::printf(
        "%-8s hits %.4f same; colours: %d of %d differ; wall %d (reference %d), glass over the wall %d "
        "(reference %d); %llu secondary rays\n",
        s.name, hits.fraction(), differ, pixels, blue, blueRef, glass, glassRef,
        static_cast<unsigned long long>(stats.secondaryRays));
    EXPECT_GE(hits.fraction(), 0.99) << s.name;
    EXPECT_LE(differ, pixels / 100) << s.name;
    EXPECT_NEAR(blue, blueRef, std::max(10, blueRef / 20)) << s.name;
    EXPECT_NEAR(glass, glassRef, std::max(10, glassRef / 10)) << s.name;
    if (s.name == std::string("under")) {
      EXPECT_GT(glassRef, 20) << "the glass is not seen against the wall";
    }
    EXPECT_GT(stats.secondaryRays, 0u) << s.name;
  }
}

TEST(SeeThrough, HazedAndLitByAnotherSunTheCasterStillSeesWhatTheReferenceSees) {
  // Each layer a secondary ray blends is hazed at its own range and lit by the frame's sun
  const auto terrain = deckAndGlass();
  const TerrainView& view = terrain->view();
  RenderSettings settings;
  settings.hazeRangeM = 150.0;
  settings.sun = SunDirection{120.0, 25.0};
  Renderer renderer(view, settings, 2);
  const ReferenceRenderer reference(view);
  for (const DeckView& s : kViews) {
    const ViewRequest request = requestFor(s);
    const Frame fast = renderer.render(request);
    const Frame ref = reference.render(request, settings);
    const int differ = pixelsDiffering(fast, ref, 24);
    std::printf("%-8s hazed and relit: %d pixels differ\n", s.name, differ);
    // (Measured 0–27 of 27,648; unhazed layers behind the first: 126–142)
    EXPECT_LE(differ, fast.image.widthPx() * fast.image.heightPx() / 400) << s.name;
  }
}

// The deck scene's ground: a plane, `atOriginM` at voxel (0, 0), rising `riseX` and `riseY` metres
// a voxel east and north (its bilinear surface between voxel centres is the plane itself).
struct GroundPlane {
  double atOriginM = kGroundM, riseX = 0.0, riseY = 0.0;
};

// How far below the ground the points of `frame` (each pixel's range along its ray) lie: the pixels
// more than `toleranceM` below, and the deepest; and the pixels that see no terrain.
struct UnderGround {
  int pixels = 0;
  double deepestM = 0.0;
  int sky = 0;
};
UnderGround underGround(const Frame& frame, const TerrainGeometry& g, const RenderSettings& settings,
                        const GroundPlane& ground, double toleranceM) {
  const ViewGeometry geo(frame.pose, frame.intrinsics, g, settings);
  UnderGround under;
  for (int v = 0; v < frame.intrinsics.heightPx; ++v) {
    for (int u = 0; u < frame.intrinsics.widthPx; ++u) {
      const float range = frame.rangeM[static_cast<std::size_t>(v * frame.intrinsics.widthPx + u)];
      if (std::isinf(range)) {
        ++under.sky;
        continue;
      }
      const glm::dvec3 p =
          frame.pose.positionM + static_cast<double>(range) * glm::normalize(geo.ray(u + 0.5, v + 0.5));
      const double groundM = ground.atOriginM + ground.riseX * (p.x - g.originM.x) / g.spacingM +
                             ground.riseY * (p.y - g.originM.y) / g.spacingM;
      under.pixels += p.z < groundM - toleranceM;
      under.deepestM = std::max(under.deepestM, groundM - p.z);
    }
  }
  return under;
}

// Renders `request` with both renderers (range images, no haze) and expects secondary rays, every
// pixel on the terrain, and no pixel of the caster more than `toleranceM` (the reference
// `toleranceRefM`) under `ground`.
void expectNothingUnderTheGround(const TerrainView& view, const ViewRequest& request, const std::string& name,
                                 const GroundPlane& ground, double toleranceM, double toleranceRefM) {
  RenderSettings settings;
  settings.rangeImage = true;
  settings.hazeRangeM = 0.0;
  Renderer renderer(view, settings, 2);
  RenderStats stats;
  const Frame fast = renderer.render(request, &stats);
  const Frame ref = ReferenceRenderer(view).render(request, settings);
  const UnderGround under = underGround(fast, view.geometry(), settings, ground, toleranceM);
  const UnderGround underRef = underGround(ref, view.geometry(), settings, ground, toleranceRefM);
  std::printf("%-13s %llu secondary rays; under the ground: %d pixels, deepest %.3f m (reference %d, %.3f m)\n",
              name.c_str(), static_cast<unsigned long long>(stats.secondaryRays), under.pixels, under.deepestM,
              underRef.pixels, underRef.deepestM);
  EXPECT_GT(stats.secondaryRays, 0u) << name;
  EXPECT_EQ(under.pixels, 0) << name;
  EXPECT_EQ(underRef.pixels, 0) << name;
  EXPECT_EQ(under.sky + underRef.sky, 0) << name << ": every pixel looks down onto the terrain";
}

// Looking down past the deck's edge, a ray meets the surface between an edge voxel of the deck and
// the ground voxel beside it (the surface runs from the deck's top down to the ground there) at the
// height of the cavity, and goes on as a secondary ray from over the ground voxel. That voxel is
// the ground the ray falls onto: a walk that passed through it would meet the next column's side
// under the ground. On the flat ground no pixel of either renderer may lie below it.
TEST(SeeThrough, PastTheDecksEdgeTheRayFallsOntoTheGroundBesideIt) {
  const auto terrain = deckAndGlass();
  for (const DeckView& s : {kViews[2], DeckView{"straight down", 207.0, 247.0, 40.0, 30.0, -89.0, 160, 120}}) {
    // The caster's walk meets a box's top exactly; the reference samples the ray every 1/16 stick
    // voxel (3.1 cm here) and keeps the first sample inside
    expectNothingUnderTheGround(terrain->view(), requestFor(s), s.name, GroundPlane{}, 0.005, 0.04);
  }
}

// The deck on ground sloping up to the north-east. Past its uphill edges a ray meets the surface
// between the deck's edge voxel and the ground voxel beside it at the height of the cavity, below
// that ground voxel's top where the slope falls away across the ray (the surface between voxel
// centres dips under a box's top). The secondary ray starts inside the ground voxel's box; going
// steeply down it leaves that box under the ground, and the next column it meets is not what the
// ray sees (the walk once met its side metres down). No pixel may lie under the sloping ground.
TEST(SeeThrough, OnASlopeARayStartingInsideTheGroundsBoxStaysOnTheGround) {
  const GroundPlane slope{kGroundM, 0.5, 1.0};
  const auto terrain = deckAndGlass(slope.atOriginM, slope.riseX, slope.riseY);
  // Over the deck's north-east corner (voxel 107, 127: ground 280.5 m), looking down
  const double cornerGroundM = slope.atOriginM + slope.riseX * 107 + slope.riseY * 127;
  for (const double pitchDeg : {-70.0, -89.0, -90.0}) {
    ViewRequest request;
    request.pose.positionM = {215.0, 255.0, cornerGroundM + 40.0};
    request.pose.headingRad = radians(200.0);
    request.pose.pitchRad = radians(pitchDeg);
    request.display = Intrinsics::fromHorizontalFov(161, 121, radians(50.0));
    // The walk's boxes have flat tops: on this slope a box's top lies up to (0.5 + 1.0) / 2 m under
    // the plane at its corners. Allowed that, and 1 cm (the caster) or 5 cm (the reference, whose
    // samples are 3.1 cm apart).
    expectNothingUnderTheGround(terrain->view(), request, "pitch " + std::to_string(static_cast<int>(pitchDeg)), slope,
                                0.76, 0.8);
  }
}

// A secondary ray straight down or up never leaves the column it starts in. Started inside the
// box of a ground voxel on the slope (voxel 108, 127: its top 281 m; the start 0.5 m under it):
// going down it is met where it starts, in the ground's colour; going up it climbs clear into the
// sky. (A walk that waited for the ray to leave the column returned an infinite range for both.)
TEST(SeeThrough, AVerticalSecondaryRayEndsInItsOwnColumn) {
  const auto terrain = deckAndGlass(kGroundM, 0.5, 1.0);
  const TerrainView& view = terrain->view();
  RenderSettings settings;
  settings.hazeRangeM = 0.0;
  const Intrinsics k = Intrinsics::fromHorizontalFov(161, 121, radians(50.0));
  const glm::dvec2 start{215.4, 253.4};  // over voxel (107.7, 126.7): column (108, 127)
  const double startZ = 280.5;
  for (const double dz : {-1.0, 1.0}) {
    Pose pose;
    pose.positionM = {start.x, start.y, startZ - 40.0 * dz};
    pose.pitchRad = radians(90.0 * dz);
    const ViewGeometry geo(pose, k, view.geometry(), settings);
    const CasterFrame f(view, geo, settings, terrainCeilingQ(view), basePlaneColour(view), nullptr, nullptr);
    CasterThread t;
    TileWindows window;
    const SeenThrough seen = seeThrough(f, t, glm::dvec3{0.0, 0.0, dz}, 40.0, window);
    const Rgb c = seen.colour;
    std::printf("straight %s: range %.2f m, colour %.0f %.0f %.0f\n", dz < 0 ? "down" : "up", seen.rangeM, c.v[0],
                c.v[1], c.v[2]);
    if (dz < 0) {
      EXPECT_FLOAT_EQ(seen.rangeM, 40.0f) << "met where it starts";
      const Rgb ground{unpackRgb(kGround).v * f.shading.light().flat()};  // no haze
      for (int ch = 0; ch < 3; ++ch) EXPECT_FLOAT_EQ(c.v[ch], ground.v[ch]) << "the ground's colour, lit";
    } else {
      EXPECT_TRUE(std::isinf(seen.rangeM)) << "the sky";
      float skyRange = 0.0f;
      const Rgb sky = f.missed(1.0, 1.0, skyRange);
      for (int ch = 0; ch < 3; ++ch) EXPECT_FLOAT_EQ(c.v[ch], sky.v[ch]) << "the sky straight up";
    }
  }
}

TEST(SeeThrough, UnderTheDeckTheWallShowsAndTheDeckAboveIt) {
  const auto terrain = deckAndGlass();
  RenderSettings settings;
  settings.hazeRangeM = 0.0;
  Renderer renderer(terrain->view(), settings, 1);
  // Level, 2.5 m up, looking north at the deck's middle from 40 m: the wall (100 m off, 20 m tall)
  // fills the cavity's rows, the deck's red the rows of its 5 … 6 m.
  ViewRequest request;
  request.pose.positionM = {207.0, 200.0, kGroundM + 2.5};
  request.display = Intrinsics::fromHorizontalFov(100, 200, radians(20.0));
  const Frame frame = renderer.render(request);
  const Intrinsics& k = frame.intrinsics;
  const int u = static_cast<int>(k.cxPx);
  const auto rowAt = [&](double heightM, double distanceM) {
    return static_cast<int>(k.cyPx - k.fyPx * (kGroundM + heightM - request.pose.positionM.z) / distanceM);
  };
  const auto colourOf = [&](int v) {
    const std::uint8_t* p = frame.image.row(v) + 3 * u;
    return rgb(p[0], p[1], p[2]);
  };
  const auto near = [](std::uint32_t a, std::uint32_t b) {
    for (int c = 0; c < 3; ++c)
      if (std::abs(static_cast<int>((a >> (8 * c)) & 0xFF) - static_cast<int>((b >> (8 * c)) & 0xFF)) > 30)
        return false;
    return true;
  };
  // The deck spans 40 … 54 m off. A ray that climbs less than to its underside (5 m) at its back
  // passes under it, and one that falls less than to the ground at the wall (100 m) meets the wall
  int wallRows = 0, redRows = 0;
  for (int v = rowAt(5.0, 54.0) + 2; v < rowAt(0.0, 100.0) - 1; ++v, ++wallRows) {
    EXPECT_TRUE(near(colourOf(v), kBlue)) << "row " << v << " under the deck is not the wall behind it";
  }
  // Above those: the deck's underside, then its front face up to 6 m, red
  for (int v = rowAt(6.0, 40.0) + 2; v < rowAt(5.0, 54.0) - 1; ++v, ++redRows) {
    EXPECT_TRUE(near(colourOf(v), kRed)) << "row " << v << " is not the deck's red";
  }
  EXPECT_GT(wallRows, 10);
  EXPECT_GT(redRows, 5);
}

TEST(SeeThrough, ANearlyLevelRayCrossingATexelBoundaryGoesThrough) {
  // The deck on high ground (2,500 m: heights near 50,000 quanta, where a double's rounding is
  // coarser), looking north under it: the middle row's ray climbs a ten-millionth of a radian, from
  // a few micrometres under the height of a texel boundary in the cavity (texels are 0.5 m from the
  // deck's top: 2,503.5 m is one), so it crosses that boundary 40 … 50 m off, inside the deck's
  // columns, at a slope so small that a walk finding its texel again from the height it reached
  // (not stepping texel by texel) stays on the boundary for ever.
  constexpr double kHighM = 2500.0;
  const auto terrain = deckAndGlass(kHighM);
  RenderSettings settings;
  settings.hazeRangeM = 0.0;
  Renderer renderer(terrain->view(), settings, 1);
  ViewRequest request;
  request.display = Intrinsics::fromHorizontalFov(100, 200, radians(20.0));
  request.pose.positionM = {207.0, 200.0, kHighM + 3.5};
  const Intrinsics frameK = renderer.render(request).intrinsics;  // the frame's, margins and all
  const int row = static_cast<int>(frameK.cyPx);
  // Pitched so that the row's ray, (cy − row − ½) / fy below the axis, climbs 1e-7
  request.pose.pitchRad = std::atan((row + 0.5 - frameK.cyPx) / frameK.fyPx) + 1e-7;
  for (const double crossingM : {40.0, 45.0, 50.0}) {
    request.pose.positionM.z = kHighM + 3.5 - crossingM * 1e-7;
    RenderStats stats;
    const Frame frame = renderer.render(request, &stats);
    EXPECT_GT(stats.secondaryRays, 100u);
    const std::uint8_t* p = frame.image.row(row) + 3 * static_cast<int>(frameK.cxPx);
    EXPECT_LT(std::abs(p[2] - 220), 30) << "the ray under the deck does not reach the wall (crossing at " << crossingM
                                        << " m)";
  }
}

TEST(SeeThrough, FarAwayTheCavitiesAreFilledAndNoRayGoesThrough) {
  const auto terrain = deckAndGlass();
  const TerrainView& view = terrain->view();
  RenderSettings settings;
  settings.rangeImage = true;
  settings.hazeRangeM = 0.0;
  // At quality 4 a level-0 voxel is drawn while it spans 4 pixels, here up to 86 m; the deck is
  // 140 … 154 m off, drawn at level 1
  settings.quality = 4.0;
  Renderer renderer(view, settings, 2);
  const ReferenceRenderer reference(view);
  const ViewRequest request = requestFor({"far", 207.0, 100.0, 20.0, 0.0, -5.0, 160, 120});
  RenderStats stats;
  const Frame fast = renderer.render(request, &stats);
  const Frame ref = reference.render(request, settings);
  const int red = pixelsNear(fast, kRed, 40), redRef = pixelsNear(ref, kRed, 40);
  std::printf("far: deck red %d (reference %d), %llu secondary rays\n", red, redRef,
              static_cast<unsigned long long>(stats.secondaryRays));
  EXPECT_EQ(stats.secondaryRays, 0u);
  // The filled deck: a solid red block, its cavity the deck's colour (not black, not the wall)
  EXPECT_GT(red, 100);
  EXPECT_NEAR(red, redRef, std::max(3, redRef / 5));
}

}  // namespace
}  // namespace fieldcast::core::test
