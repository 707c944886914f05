// A few rendered views checked in as small PNGs (tests/render/golden), compared with a tolerance:
// at most 0.5% of the pixels may differ by more than 12 levels in any channel, and none by more
// than 96 (a silhouette moving by a pixel). Regenerate with FIELDCAST_UPDATE_GOLDEN=1 after an
// intended change, and look at the new images before committing them. Each pose is also checked
// against the reference renderer, since the stored images are the caster's own.
#include "RenderTestUtil.h"  // compareHits: the accuracy sweep's criterion

#include <ig_core/ReferenceRenderer.h>
#include <ig_core/Renderer.h>
#include <ig_core/SyntheticTerrain.h>

#include <fieldcast/Conventions.h>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace fieldcast::core {
namespace {

struct GoldenView {
  const char* name;
  double heading, pitch, altitude, fov;
  bool grey;
};

const MemoryTerrain& terrain() {
  static const std::unique_ptr<MemoryTerrain> t = makeSyntheticTerrain({SyntheticKind::Hills, 1024, 2.0, 6, 21});
  return *t;
}

RenderSettings settingsFor(const GoldenView& g) {
  RenderSettings settings;
  settings.colourMode = g.grey ? FrameColour::Grey : FrameColour::Rgb;
  return settings;
}

ViewRequest requestFor(const GoldenView& g) {
  const TerrainView& view = terrain().view();
  ViewRequest r;
  r.pose.positionM = {1000.0, 900.0, view.heightAtM(1000.0, 900.0) + g.altitude};
  r.pose.headingRad = radians(g.heading);
  r.pose.pitchRad = radians(g.pitch);
  r.display = Intrinsics::fromHorizontalFov(120, 80, radians(g.fov));
  return r;
}

Frame renderView(const GoldenView& g, bool range = false) {
  RenderSettings settings = settingsFor(g);
  settings.rangeImage = range;
  Renderer renderer(terrain().view(), settings, 2);
  return renderer.render(requestFor(g));
}

std::string goldenPath(const char* name) { return std::string(FIELDCAST_SOURCE_DIR) + "/tests/render/golden/" + name; }

class RenderGolden : public ::testing::TestWithParam<GoldenView> {};

TEST_P(RenderGolden, MatchesTheStoredImage) {
  const GoldenView g = GetParam();
  const Frame f = renderView(g);
  const int channels = g.grey ? 1 : 3;
  const std::string path = goldenPath(g.name);
  if (std::getenv("FIELDCAST_UPDATE_GOLDEN") != nullptr) {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    ASSERT_TRUE(
        out->open(path, OIIO::ImageSpec(f.image.widthPx(), f.image.heightPx(), channels, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, f.image.bytes().data()));
    out->close();
    GTEST_SKIP() << "wrote " << path;
  }
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in) << path << ": " << OIIO::geterror();
  const OIIO::ImageSpec& spec = in->spec();
  ASSERT_EQ(spec.width, f.image.widthPx());
  ASSERT_EQ(spec.height, f.image.heightPx());
  ASSERT_EQ(spec.nchannels, channels);
  std::vector<std::uint8_t> golden(static_cast<std::size_t>(spec.width * spec.height * channels));
  ASSERT_TRUE(in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, golden.data()));
  int failing = 0;
  int worst = 0;
  const auto bytes = f.image.bytes();
  for (std::size_t p = 0; p < golden.size(); p += static_cast<std::size_t>(channels)) {
    int diff = 0;
    for (int c = 0; c < channels; ++c) diff = std::max(diff, std::abs(int{bytes[p + c]} - int{golden[p + c]}));
    worst = std::max(worst, diff);
    if (diff > 12) ++failing;
  }
  const double fraction = static_cast<double>(failing) * channels / static_cast<double>(golden.size());
  EXPECT_LE(fraction, 0.005) << path << ": " << failing << " pixels differ by more than 12";
  EXPECT_LE(worst, 96) << path;
}

// The golden images are the caster's own renders: they catch a change, not an error. So each
// golden pose is also rendered by the reference renderer, and the caster must hit the reference's
// voxel or a neighbour (at the level used) in at least 99.5% of the pixels, or both see the sky,
// or they disagree on sky within a voxel of the terrain's edge: the accuracy sweep's criterion
// (compareHits, ig_core/render/tests/RenderTestUtil.h).
TEST_P(RenderGolden, PoseAgreesWithTheReferenceRenderer) {
  const GoldenView g = GetParam();
  const TerrainView& view = terrain().view();
  RenderSettings settings = settingsFor(g);
  settings.rangeImage = true;
  const Frame fast = renderView(g, true);
  const Frame ref = ReferenceRenderer(view).render(requestFor(g), settings);
  const test::HitAgreement a = test::compareHits(fast, ref, view.geometry(), settings);
  const int pixels = a.pixels;
  const int same = a.same;
  const double fraction = static_cast<double>(same) / pixels;
  std::printf("%s: %.5f of %d pixels on the reference's voxel or a neighbour\n", g.name, fraction, pixels);
  EXPECT_GE(fraction, 0.995) << g.name;
}

INSTANTIATE_TEST_SUITE_P(Views, RenderGolden,
                         ::testing::Values(GoldenView{"oblique.png", 40.0, -20.0, 150.0, 60.0, false},
                                           GoldenView{"horizon.png", 250.0, -2.0, 40.0, 70.0, false},
                                           GoldenView{"down_wide.png", 130.0, -80.0, 600.0, 90.0, false},
                                           GoldenView{"grey_low.png", 320.0, -8.0, 60.0, 45.0, true}),
                         [](const auto& param) {
                           std::string n = param.param.name;
                           return n.substr(0, n.find('.'));
                         });

}  // namespace
}  // namespace fieldcast::core
