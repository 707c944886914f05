// The world beyond the terrain's edge: a flat base plane at quantised height 0 in the mean colour
// of the top level, in the haze (RENDERER.md, "Beyond the edge"), drawn alike by the fast caster
// and the reference renderer.
#include "ColumnCaster.h"
#include "RenderTestUtil.h"
#include "Shading.h"

#include <ig_core/Renderer.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace fieldcast::core::test {
namespace {

struct EdgeView {
  Frame fast;
  Frame reference;
  RenderSettings settings;
};

// A view of the hills (x, y in 0..1022 m) from `positionM`, caster and reference.
EdgeView renderBoth(const glm::dvec3& positionM, double headingDeg, double pitchDeg) {
  const TerrainView& view = hills().view();
  EdgeView out;
  out.settings.rangeImage = true;
  ViewRequest request;
  request.pose.positionM = positionM;
  request.pose.headingRad = radians(headingDeg);
  request.pose.pitchRad = radians(pitchDeg);
  request.display = Intrinsics::fromHorizontalFov(120, 80, radians(60.0));
  Renderer renderer(view, out.settings, 2);
  out.fast = renderer.render(request);
  out.reference = ReferenceRenderer(view).render(request, out.settings);
  return out;
}

double ceilingM(const TerrainView& view) { return view.geometry().heightM(terrainCeilingQ(view)); }

// From inside, 322 m from the east edge and above every hill, looking east and down: below
// the horizon every pixel sees terrain or, past the edge, the base plane in its colour and the
// haze; above it, sky. (Before the base plane the rays past the edge saw the sky below the
// horizon: the world ended at the edge.)
TEST(BeyondTheEdge, FromInsideTheBasePlaneFillsTheViewBelowTheHorizon) {
  const TerrainView& view = hills().view();
  const TerrainGeometry& g = view.geometry();
  const EdgeView e = renderBoth({700.0, 500.0, ceilingM(view) + 20.0}, 90.0, -20.0);
  const HitAgreement a = compareHits(e.fast, e.reference, g, e.settings);
  std::printf("inside looking out: %.4f same (%d mismatches, %d at the edge)\n", a.fraction(), a.skyMismatch, a.atEdge);
  EXPECT_GE(a.fraction(), 0.995);

  const ViewGeometry geo(e.fast.pose, e.fast.intrinsics, g, e.settings);
  const Shading shading(e.settings);
  const Rgb base = unpackRgb(basePlaneColour(view));
  const int w = e.fast.intrinsics.widthPx;
  int plane = 0;
  int sky = 0;
  int terrain = 0;
  double colourError = 0.0;
  for (int v = 0; v < e.fast.intrinsics.heightPx; ++v) {
    for (int u = 0; u < w; ++u) {
      const std::size_t k = static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + u;
      const glm::dvec3 d = geo.ray(u + 0.5, v + 0.5);
      const float range = e.fast.rangeM[k];
      if (d.z >= 0.0) {  // the camera is above all the terrain
        EXPECT_TRUE(std::isinf(range)) << "pixel " << u << "," << v << " above the horizon";
        ++sky;
        continue;
      }
      ASSERT_FALSE(std::isinf(range)) << "pixel " << u << "," << v << " below the horizon sees the sky";
      const glm::dvec3 p = e.fast.pose.positionM + static_cast<double>(range) * glm::normalize(d);
      if (insideGridM(g, p) > -g.spacingM) {
        ++terrain;
        continue;
      }
      ++plane;
      EXPECT_NEAR(p.z, g.heightBaseM, 1e-4 * range) << "pixel " << u << "," << v;
      const Rgb expected = shading.terrain(base, range);
      for (int c = 0; c < 3; ++c) {
        const int got = e.fast.image.row(v)[3 * u + c];
        const int want = static_cast<int>(std::lround(std::clamp(expected.v[c], 0.0f, 255.0f)));
        ASSERT_LE(std::abs(got - want), 1) << "pixel " << u << "," << v << " channel " << c;
        colourError += std::abs(got - static_cast<int>(e.reference.image.row(v)[3 * u + c]));
      }
    }
  }
  const int pixels = w * e.fast.intrinsics.heightPx;
  std::printf("  %d of %d pixels on the base plane, %d terrain, %d sky; mean colour difference to the reference %.3f\n",
              plane, pixels, terrain, sky, plane ? colourError / (3.0 * plane) : 0.0);
  EXPECT_GE(plane, pixels / 5);  // the view does look past the edge
  EXPECT_GE(terrain, pixels / 10);
  EXPECT_GE(sky, pixels / 10);
  EXPECT_LE(colourError / (3.0 * std::max(plane, 1)), 1.0);
}

// From outside, 300 m east of the grid and 100 m above the base plane, looking west and down: the
// grid's side is a cliff from the edge down to the base plane, not a wall without end below it.
TEST(BeyondTheEdge, FromOutsideTheSidesEndAtTheBasePlane) {
  const TerrainView& view = hills().view();
  const TerrainGeometry& g = view.geometry();
  for (const double pitchDeg : {-10.0, -30.0}) {
    const EdgeView e = renderBoth({1322.0, 500.0, g.heightBaseM + 100.0}, 270.0, pitchDeg);
    const HitAgreement a = compareHits(e.fast, e.reference, g, e.settings);
    std::printf("outside, pitch %.0f: %.4f same (%d mismatches, %d at the edge)\n", pitchDeg, a.fraction(),
                a.skyMismatch, a.atEdge);
    EXPECT_GE(a.fraction(), 0.995);
    const ViewGeometry geo(e.fast.pose, e.fast.intrinsics, g, e.settings);
    const int w = e.fast.intrinsics.widthPx;
    int side = 0;
    for (const Frame* frame : {&e.fast, &e.reference}) {
      for (int v = 0; v < frame->intrinsics.heightPx; ++v) {
        for (int u = 0; u < w; ++u) {
          const float range = frame->rangeM[static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + u];
          const glm::dvec3 d = geo.ray(u + 0.5, v + 0.5);
          if (d.z < 0.0) {
            ASSERT_FALSE(std::isinf(range)) << "pixel " << u << "," << v << " below the horizon";
          }
          if (std::isinf(range)) continue;
          const glm::dvec3 p = frame->pose.positionM + static_cast<double>(range) * glm::normalize(d);
          ASSERT_GE(p.z, g.heightBaseM - 0.01) << (frame == &e.fast ? "caster" : "reference") << " pixel " << u << ","
                                               << v << " sees below the base plane";
          if (std::abs(insideGridM(g, p)) < 2.0 * g.spacingM && p.z > g.heightBaseM + 1.0) ++side;
        }
      }
    }
    EXPECT_GT(side, 0) << "the view should see the grid's side";
  }
}

}  // namespace
}  // namespace fieldcast::core::test
