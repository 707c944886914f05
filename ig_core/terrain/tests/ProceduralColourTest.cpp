#include <ig_core/TerrainColour.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <vector>

namespace fieldcast::core {
namespace {

// A 64×64 grid: a ridge running north-south (west slope rising east, east slope falling), 1 m
// voxels, heights in 10 cm steps; the western quarter is sea.
struct Ridge {
  TerrainGeometry geometry;
  std::vector<std::uint16_t> heightQ;
  Ridge() {
    geometry.widthVox = 64;
    geometry.heightVox = 64;
    geometry.spacingM = 1.0;
    geometry.heightBaseM = -5.0;
    geometry.heightStepM = 0.1;
    for (int j = 0; j < 64; ++j) {
      for (int i = 0; i < 64; ++i) {
        const double z = i < 16 ? -2.0 : 20.0 + 0.5 * (32 - std::abs(i - 40));  // sea, then a ridge at x = 40
        heightQ.push_back(static_cast<std::uint16_t>((z + 5.0) / 0.1));
      }
    }
  }
  std::uint32_t brightness(const std::vector<std::uint32_t>& c, int i, int j) const {
    const std::uint32_t v = c[static_cast<std::size_t>(j) * 64 + i];
    return (v & 0xFFu) + ((v >> 8) & 0xFFu) + ((v >> 16) & 0xFFu);
  }
};

TEST(ProceduralColour, TheSlopeFacingTheSunIsBrighter) {
  const Ridge r;
  ProceduralColourOptions sunInTheWest;
  sunInTheWest.sunAzimuthDeg = 270.0;
  sunInTheWest.noise = 0.0;
  const std::vector<std::uint32_t> west = bakeProceduralColour(r.geometry, r.heightQ, {}, sunInTheWest);
  EXPECT_GT(r.brightness(west, 30, 32), r.brightness(west, 50, 32));  // the west face is lit
  ProceduralColourOptions sunInTheEast = sunInTheWest;
  sunInTheEast.sunAzimuthDeg = 90.0;
  const std::vector<std::uint32_t> east = bakeProceduralColour(r.geometry, r.heightQ, {}, sunInTheEast);
  EXPECT_LT(r.brightness(east, 30, 32), r.brightness(east, 50, 32));
  ProceduralColourOptions flatLight = sunInTheWest;
  flatLight.hillshade = 0.0;
  const std::vector<std::uint32_t> flat = bakeProceduralColour(r.geometry, r.heightQ, {}, flatLight);
  EXPECT_EQ(flat[32 * 64 + 30], flat[32 * 64 + 50]);  // same palette colour on both faces
}

TEST(ProceduralColour, SeaIsBlueAndGreyModeIsGrey) {
  const Ridge r;
  ProceduralColourOptions options;
  const std::vector<std::uint32_t> colour = bakeProceduralColour(r.geometry, r.heightQ, {}, options);
  const std::uint32_t sea = colour[32 * 64 + 5];
  EXPECT_GT((sea >> 16) & 0xFFu, sea & 0xFFu);  // more blue than red
  EXPECT_EQ(sea >> 24, 255u);
  options.output = ColourOutput::Grey;
  const std::vector<std::uint32_t> grey = bakeProceduralColour(r.geometry, r.heightQ, {}, options);
  for (const std::uint32_t v : grey) {
    ASSERT_EQ(v & 0xFFu, (v >> 8) & 0xFFu);
    ASSERT_EQ(v & 0xFFu, (v >> 16) & 0xFFu);
  }
  const std::vector<std::uint8_t> wrongSize(10, 0);
  EXPECT_THROW(bakeProceduralColour(r.geometry, r.heightQ, wrongSize, options), std::invalid_argument);
}

TEST(ProceduralColour, SameOptionsSameColoursForAnyThreadCount) {
  const Ridge r;
  ProceduralColourOptions one;
  one.threads = 1;
  ProceduralColourOptions two = one;
  two.threads = 2;
  EXPECT_EQ(bakeProceduralColour(r.geometry, r.heightQ, {}, one), bakeProceduralColour(r.geometry, r.heightQ, {}, two));
}

}  // namespace
}  // namespace fieldcast::core
