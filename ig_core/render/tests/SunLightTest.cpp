// The frame's sun (RenderSettings::sun, TerrainLight.h): the colours' own sun draws them as
// stored; another sun brightens the slopes that face it and darkens those that turn away, in the
// fast caster and the reference renderer alike; below the horizon the terrain, the sticks, the
// sky and the entities go dark.
#include "RenderTestUtil.h"
#include "TerrainLight.h"

#include <ig_core/Renderer.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

namespace fieldcast::core::test {
namespace {

double luma(const Frame& f, int u, int v) {
  const std::uint8_t* p = f.image.row(v) + 3 * u;
  return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
}

double meanLuma(const Frame& f) {
  double sum = 0.0;
  for (int v = 0; v < f.image.heightPx(); ++v)
    for (int u = 0; u < f.image.widthPx(); ++u) sum += luma(f, u, v);
  return sum / (f.image.widthPx() * f.image.heightPx());
}

ViewRequest oblique(const TerrainView& view) {
  ViewRequest r;
  r.pose = poseAbove(view, 300.0, 250.0, 60.0, 40.0, -12.0);
  r.display = Intrinsics::fromHorizontalFov(200, 150, radians(70.0));
  return r;
}

ViewRequest lookingDown(const TerrainView& view) {
  ViewRequest r;
  r.pose = poseAbove(view, 512.0, 512.0, 700.0, 0.0, -89.0);
  r.display = Intrinsics::fromHorizontalFov(200, 200, radians(60.0));
  return r;
}

RenderSettings litBy(double azimuthDeg, double elevationDeg) {
  RenderSettings s;
  s.rangeImage = true;
  s.sun = {azimuthDeg, elevationDeg};
  return s;
}

// The ground's east–west slope (rise per metre east) under each pixel of a frame looking down.
std::vector<double> eastSlopes(const TerrainView& view, const Frame& f) {
  const ViewGeometry geo(f.pose, f.intrinsics, view.geometry(), RenderSettings{});
  std::vector<double> slopes;
  for (int v = 0; v < f.intrinsics.heightPx; ++v)
    for (int u = 0; u < f.intrinsics.widthPx; ++u) {
      const double r = f.rangeM[static_cast<std::size_t>(v * f.intrinsics.widthPx + u)];
      const glm::dvec3 p = f.pose.positionM + r * glm::normalize(geo.ray(u + 0.5, v + 0.5));
      slopes.push_back((view.heightAtM(p.x + 4.0, p.y) - view.heightAtM(p.x - 4.0, p.y)) / 8.0);
    }
  return slopes;
}

TEST(TerrainLight, TheColoursOwnSunLeavesEveryFactorAtOne) {
  RenderSettings s;
  s.sun = s.colourSun = {120.0, 25.0};
  const TerrainLight same(s);
  EXPECT_FALSE(same.relit());
  EXPECT_EQ(same.terrain(0.7f, -0.4f), 1.0f);
  EXPECT_EQ(same.flat(), 1.0f);
  EXPECT_EQ(same.sky(), 1.0f);

  s.sun = {120.0 - 360.0, 25.0};  // the same sun written another way
  EXPECT_FALSE(TerrainLight(s).relit());

  // Colours baked under a low sun (2°, already dim): a sun a hair from it changes nothing much.
  s.colourSun = {120.0, 2.0};
  s.sun = {120.0001, 2.0001};
  const TerrainLight low(s);
  EXPECT_TRUE(low.relit());
  EXPECT_NEAR(low.flat(), 1.0f, 1e-3f);
  EXPECT_NEAR(low.sky(), 1.0f, 1e-3f);
  EXPECT_NEAR(low.terrain(0.3f, -0.2f), 1.0f, 1e-3f);

  s.colourSun = {120.0, 25.0};
  s.sun = {300.0, 25.0};
  const TerrainLight other(s);
  EXPECT_TRUE(other.relit());
  // The new sun in the west-north-west: a slope rising to the east faces it, one falling to the east turns away.
  EXPECT_GT(other.terrain(0.5f, 0.0f), 1.2f);
  EXPECT_LT(other.terrain(-0.5f, 0.0f), 0.8f);
}

TEST(TerrainLight, ModelsAreLitAsBeforeByTheDefaultSunAndDarkAtNight) {
  const TerrainLight day{RenderSettings{}};
  const glm::dvec3 up{0.0, 0.0, 1.0};
  EXPECT_NEAR(day.model(up), 0.55 + 0.45 * std::sin(radians(40.0)), 1e-12);
  EXPECT_NEAR(day.model({1.0, 0.0, 0.0}), 0.55, 1e-12);  // an east face: the sun is in the north-west
  const TerrainLight night{litBy(315.0, -20.0)};
  EXPECT_NEAR(night.model(up), 0.55 * 0.05, 1e-9);
}

TEST(SunLight, ASunAHairFromTheColoursOwnDrawsTheSamePicture) {
  // The relit path scales by factors within a millionth of 1 here: the same picture within the
  // rounding of a grey level, on bare and furnished hills (sticks, roofs), by both renderers.
  for (const MemoryTerrain* terrain : {&hills(), &furnishedHills()}) {
    const TerrainView& view = terrain->view();
    const ViewRequest r = oblique(view);
    Renderer stored(view, RenderSettings{}, 2);
    Renderer relit(view, litBy(315.0001, 40.0001), 2);
    const Frame a = stored.render(r);
    const Frame b = relit.render(r);
    int off = 0;
    for (int v = 0; v < a.image.heightPx(); ++v)
      for (int u = 0; u < a.image.widthPx(); ++u) off += std::abs(luma(a, u, v) - luma(b, u, v)) > 1.0;
    EXPECT_EQ(off, 0);
  }
}

TEST(SunLight, SlopesFacingTheSunAreBrighterInBothRenderers) {
  const TerrainView& view = hills().view();
  const ViewRequest r = lookingDown(view);
  const ReferenceRenderer reference(view);
  for (const bool fast : {true, false}) {
    SCOPED_TRACE(fast ? "fast caster" : "reference renderer");
    const auto render = [&](const RenderSettings& s) {
      if (!fast) return reference.render(r, s);
      Renderer renderer(view, s, 2);
      return renderer.render(r);
    };
    const Frame east = render(litBy(90.0, 30.0));
    const Frame west = render(litBy(270.0, 30.0));
    const std::vector<double> slopes = eastSlopes(view, east);
    double facingEast[2] = {0, 0}, facingWest[2] = {0, 0};
    int nEast = 0, nWest = 0;
    for (int v = 0, k = 0; v < east.intrinsics.heightPx; ++v)
      for (int u = 0; u < east.intrinsics.widthPx; ++u, ++k) {
        const double s = slopes[static_cast<std::size_t>(k)];
        if (s < -0.25) {  // falls to the east: faces east
          facingEast[0] += luma(east, u, v), facingEast[1] += luma(west, u, v), ++nEast;
        } else if (s > 0.25) {
          facingWest[0] += luma(east, u, v), facingWest[1] += luma(west, u, v), ++nWest;
        }
      }
    ASSERT_GT(nEast, 500);
    ASSERT_GT(nWest, 500);
    EXPECT_GT(facingEast[0] / facingEast[1], 1.3);  // facing the sun in the east: brighter
    EXPECT_LT(facingWest[0] / facingWest[1], 0.77);
  }
}

// Mean absolute luma difference between two frames.
double meanDifference(const Frame& a, const Frame& b) {
  double diff = 0.0;
  for (int v = 0; v < a.image.heightPx(); ++v)
    for (int u = 0; u < a.image.widthPx(); ++u) diff += std::abs(luma(a, u, v) - luma(b, u, v));
  return diff / (a.image.widthPx() * a.image.heightPx());
}

TEST(SunLight, TheFastCasterAndTheReferenceRelightAlike) {
  // The two renderers interpolate colours differently (crossings against bilinear), so their
  // pictures differ a little with the stored colours (0.2 grey levels on average); relit (a
  // factor per voxel, interpolated as the colours are), within one and a half. (A nearest-voxel
  // factor in one of them differed by 4.8.)
  const TerrainView& view = hills().view();
  const ViewRequest r = lookingDown(view);
  const RenderSettings evening = litBy(200.0, 12.0);
  const auto both = [&](const RenderSettings& s) {
    Renderer renderer(view, s, 2);
    return std::pair{renderer.render(r), ReferenceRenderer(view).render(r, s)};
  };
  const auto [fastStored, referenceStored] = both(RenderSettings{});
  const auto [fast, reference] = both(evening);
  EXPECT_GT(std::abs(meanLuma(reference) - meanLuma(referenceStored)), 5.0);  // the evening sun changed it
  EXPECT_NEAR(meanLuma(fast), meanLuma(reference), 0.01 * meanLuma(reference));
  const double stored = meanDifference(fastStored, referenceStored);
  const double relit = meanDifference(fast, reference);
  std::printf("mean |fast - reference| luma: stored colours %.2f, relit %.2f\n", stored, relit);
  EXPECT_LT(relit, 1.5);
  EXPECT_LT(stored, 0.5);
}

TEST(SunLight, AtNightTheTerrainTheSticksAndTheSkyAreDark) {
  const TerrainView& view = furnishedHills().view();
  ViewRequest r;
  r.pose = poseAbove(view, 380.0, 330.0, 40.0, 45.0, 0.0);  // the village and the sky beyond
  r.display = Intrinsics::fromHorizontalFov(200, 150, radians(70.0));
  Renderer day(view, litBy(315.0, 40.0), 2);  // the colours' own sun
  Renderer night(view, litBy(315.0, -20.0), 2);
  const Frame a = day.render(r);
  const Frame b = night.render(r);
  int sky = 0, bright = 0;
  for (int v = 0; v < a.image.heightPx(); ++v)
    for (int u = 0; u < a.image.widthPx(); ++u) {
      EXPECT_LE(luma(b, u, v), 0.12 * luma(a, u, v) + 1.0) << u << ", " << v;
      sky += std::isinf(a.rangeM[static_cast<std::size_t>(v * a.image.widthPx() + u)]);
      bright += luma(a, u, v) > 40.0;
    }
  EXPECT_GT(sky, 1000);  // the test sees sky and lit ground
  EXPECT_GT(bright, 10000);
  EXPECT_GT(meanLuma(a), 60.0);
  EXPECT_LT(meanLuma(b), 12.0);
}

}  // namespace
}  // namespace fieldcast::core::test
