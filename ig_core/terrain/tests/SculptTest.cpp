// Sculpting from three photographs: a known house is rendered into its three orthographic views
// (on a key colour, at a scale that does not fall on voxel edges) and carved back; the solid must
// match it (intersection over union), and each surface takes its colour from the photograph that
// faces it — the side's halves, the front's halves and the top's halves tell the mapping apart.
#include "TerrainTestUtil.h"

#include <ig_core/Sculpt.h>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

namespace fieldcast::core {
namespace {

using testing::ScratchDir;

constexpr std::uint32_t kKey = 0xFFFF00FFu;  // magenta

std::uint32_t rgb(int r, int g, int b) {
  return static_cast<std::uint32_t>(r) | (static_cast<std::uint32_t>(g) << 8) | (static_cast<std::uint32_t>(b) << 16) |
         0xFF000000u;
}

// A house 20 × 14 voxels (10 × 7 m), walls 10 high, a gable roof with its ridge front to back,
// a chimney on its left slope near the front, and a porch 3 deep in front of its right half
VoxelSolid knownHouse() {
  VoxelSolid s = emptySolid(20, 17, 17);
  for (int z = 0; z < 17; ++z)
    for (int y = 0; y < 17; ++y)
      for (int x = 0; x < 20; ++x) {
        const bool house = y < 14 && (z < 10 || (x >= z - 10 && x < 30 - z));
        const bool chimney = x == 4 && (y == 10 || y == 11);
        const bool porch = y >= 14 && x >= 11 && x < 18 && z < 5;
        if (house || chimney || porch) s.rgba[s.index(x, y, z)] = z >= 10 ? rgb(90, 90, 110) : rgb(170, 60, 40);
      }
  return s;
}

// An orthographic view of `solid` (Sculpt.h's conventions) at `pxPerVoxel`, on the key with a
// margin; each pixel shows the first voxel along its ray, or `paint(u, v)` of the object when given
enum class ViewOf { Side, Front, Top };
Silhouette render(const VoxelSolid& s, ViewOf view, double pxPerVoxel, int margin,
                  const std::function<std::uint32_t(double, double)>& paint = {}) {
  const int across = view == ViewOf::Side ? s.sizeY : s.sizeX;
  const int down = view == ViewOf::Top ? s.sizeY : s.sizeZ;
  const int w = static_cast<int>(std::ceil(across * pxPerVoxel)) + 2 * margin;
  const int h = static_cast<int>(std::ceil(down * pxPerVoxel)) + 2 * margin;
  std::vector<std::uint32_t> rgba(static_cast<std::size_t>(w * h), kKey);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const int a = static_cast<int>(std::floor((u - margin + 0.5) / pxPerVoxel));
      const int b = static_cast<int>(std::floor((v - margin + 0.5) / pxPerVoxel));
      if (a < 0 || b < 0 || a >= across || b >= down) continue;
      const int depth = view == ViewOf::Side ? s.sizeX : view == ViewOf::Front ? s.sizeY : s.sizeZ;
      for (int d = depth - 1; d >= 0; --d) {
        int x = 0, y = 0, z = 0;
        if (view == ViewOf::Side) x = d, y = a, z = s.sizeZ - 1 - b;
        if (view == ViewOf::Front) x = s.sizeX - 1 - a, y = d, z = s.sizeZ - 1 - b;
        if (view == ViewOf::Top) x = a, y = s.sizeY - 1 - b, z = d;
        if (!s.filled(x, y, z)) continue;
        rgba[static_cast<std::size_t>(v * w + u)] =
            paint ? paint((a + 0.5) / across, (b + 0.5) / down) : s.rgba[s.index(x, y, z)];
        break;
      }
    }
  return keySilhouette(w, h, std::move(rgba), {kKey, 24});
}

double intersectionOverUnion(const VoxelSolid& a, const VoxelSolid& b) {
  std::size_t both = 0, either = 0;
  for (int z = 0; z < a.sizeZ; ++z)
    for (int y = 0; y < a.sizeY; ++y)
      for (int x = 0; x < a.sizeX; ++x) {
        const bool inA = a.filled(x, y, z);
        const bool inB = x < b.sizeX && y < b.sizeY && z < b.sizeZ && b.filled(x, y, z);
        both += inA && inB, either += inA || inB;
      }
  return static_cast<double>(both) / static_cast<double>(either);
}

TEST(Sculpt, AKnownHouseIsCarvedBackFromItsThreeViews) {
  const VoxelSolid house = knownHouse();
  const SculptViews views{render(house, ViewOf::Side, 4.3, 7), render(house, ViewOf::Front, 3.7, 12),
                          render(house, ViewOf::Top, 5.1, 3)};
  const SculptResult r = sculptFromSilhouettes(views, house.sizeZ * kSolidVoxelM);
  EXPECT_EQ(r.solid.sizeX, house.sizeX);
  EXPECT_EQ(r.solid.sizeY, house.sizeY);
  EXPECT_EQ(r.solid.sizeZ, house.sizeZ);
  EXPECT_NEAR(r.widthM, 10.0, 0.2);
  EXPECT_NEAR(r.depthM, 8.5, 0.2);
  const double iou = intersectionOverUnion(house, r.solid);
  std::printf("sculpted house: %zu voxels (known %zu), intersection over union %.4f, top aspect off by %.3f\n",
              r.solid.filledCount(), house.filledCount(), iou, r.topAspectError);
  EXPECT_GE(iou, 0.95);
  // The chimney stands on the left slope, not mirrored onto the right
  EXPECT_TRUE(r.solid.filled(4, 10, 15));
  EXPECT_FALSE(r.solid.filled(15, 10, 15));
  // Colours from the views: the walls brick, the roof slate
  EXPECT_EQ(r.solid.rgba[r.solid.index(0, 5, 5)], rgb(170, 60, 40));
  EXPECT_EQ(r.solid.rgba[r.solid.index(10, 5, 15)], rgb(90, 90, 110));
  EXPECT_EQ(r.fromSide + r.fromFront + r.fromTop + r.hidden, r.solid.filledCount());
}

TEST(Sculpt, EachSurfaceTakesItsColourFromThePhotographFacingIt) {
  const VoxelSolid house = knownHouse();
  const std::uint32_t yellow = rgb(230, 220, 40), red = rgb(200, 20, 20), green = rgb(20, 180, 40),
                      cyan = rgb(20, 200, 220), blue = rgb(30, 40, 200), white = rgb(240, 240, 240);
  // Side: its left half is the back; front: its left half is the object's right; top: its upper
  // half is the front
  const SculptViews views{
      render(house, ViewOf::Side, 4.0, 5, [&](double u, double) { return u < 0.5 ? yellow : red; }),
      render(house, ViewOf::Front, 4.0, 5, [&](double u, double) { return u < 0.5 ? green : cyan; }),
      render(house, ViewOf::Top, 4.0, 5, [&](double, double v) { return v < 0.5 ? blue : white; })};
  const SculptResult r = sculptFromSilhouettes(views, house.sizeZ * kSolidVoxelM);
  const VoxelSolid& s = r.solid;
  const auto at = [&](int x, int y, int z) { return s.rgba[s.index(x, y, z)]; };
  // The roof (an open face up) from the top: front half blue, back half white
  EXPECT_EQ(at(14, 14, 4), blue);   // the porch roof, at the front
  EXPECT_EQ(at(10, 12, 16), blue);  // the ridge near the front
  EXPECT_EQ(at(10, 2, 16), white);  // the ridge near the back
  // The long walls (open to the sides) from the side photograph: front red, back yellow
  EXPECT_EQ(at(19, 12, 5), red);
  EXPECT_EQ(at(0, 12, 5), red);  // the left wall looks like the right
  EXPECT_EQ(at(19, 2, 5), yellow);
  // The gable end (open to the front only) from the front photograph: right green, left cyan
  EXPECT_EQ(at(14, 13, 8), green);
  EXPECT_EQ(at(5, 13, 8), cyan);
  EXPECT_EQ(at(5, 0, 8), cyan);  // the back looks like the front
  EXPECT_GT(r.fromSide, 0u);
  EXPECT_GT(r.fromFront, 0u);
  EXPECT_GT(r.fromTop, 0u);
}

TEST(Sculpt, ViewsThatDisagreeOrShowNothingAreRefused) {
  const VoxelSolid house = knownHouse();
  const Silhouette side = render(house, ViewOf::Side, 4.0, 5), front = render(house, ViewOf::Front, 4.0, 5);
  // A top view turned by 90°: the side's depth across, the front's width down
  VoxelSolid turned = emptySolid(house.sizeY, house.sizeX, house.sizeZ);
  for (int z = 0; z < house.sizeZ; ++z)
    for (int y = 0; y < house.sizeY; ++y)
      for (int x = 0; x < house.sizeX; ++x) turned.rgba[turned.index(y, x, z)] = house.rgba[house.index(x, y, z)];
  try {
    sculptFromSilhouettes({side, front, render(turned, ViewOf::Top, 4.0, 5)}, 8.5);
    ADD_FAILURE() << "a turned top view was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("the top view's object is 68 × 80 px"), std::string::npos) << e.what();
  }
  const Silhouette nothing = keySilhouette(8, 8, std::vector<std::uint32_t>(64, kKey), {kKey, 24});
  EXPECT_THROW(sculptFromSilhouettes({side, nothing, render(house, ViewOf::Top, 4.0, 5)}, 8.5), std::invalid_argument);
  EXPECT_THROW(sculptFromSilhouettes({side, front, render(house, ViewOf::Top, 4.0, 5)}, 0.1), std::invalid_argument);
  EXPECT_THROW(sculptFromSilhouettes({side, front, render(house, ViewOf::Top, 4.0, 5)}, 200.0), std::invalid_argument);
}

void writeImage(const std::filesystem::path& path, int w, int h, int channels,
                const std::vector<unsigned char>& pixels) {
  auto out = OIIO::ImageOutput::create(path.string());
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path.string(), OIIO::ImageSpec(w, h, channels, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
  out->close();
}

TEST(Sculpt, PhotographsAreKeyedByColourOrByTheirAlpha) {
  ScratchDir dir;
  // RGB: a 4 × 2 grey square on green; RGBA: the same by alpha
  std::vector<unsigned char> rgb(8 * 4 * 3), rgba(8 * 4 * 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) {
      const bool object = x >= 2 && x < 6 && y >= 1 && y < 3;
      const std::size_t i = static_cast<std::size_t>(y * 8 + x);
      const unsigned char c[3] = {static_cast<unsigned char>(object ? 128 : 10),
                                  static_cast<unsigned char>(object ? 128 : 250),
                                  static_cast<unsigned char>(object ? 128 : 10)};
      for (std::size_t k = 0; k < 3; ++k) rgb[i * 3 + k] = rgba[i * 4 + k] = c[k];
      rgba[i * 4 + 3] = object ? 255 : 0;
    }
  writeImage(dir.path() / "rgb.png", 8, 4, 3, rgb);
  writeImage(dir.path() / "rgba.png", 8, 4, 4, rgba);
  const auto count = [](const Silhouette& s) { return std::count(s.inside.begin(), s.inside.end(), 1); };
  EXPECT_EQ(count(readSilhouette(dir.path() / "rgb.png", {0xFF00FF00u, 24})), 8);
  EXPECT_EQ(count(readSilhouette(dir.path() / "rgba.png", {})), 8);
  try {
    (void)readSilhouette(dir.path() / "rgb.png", {});
    ADD_FAILURE() << "an RGB image without a key was taken";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no alpha channel"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)readSilhouette(dir.path() / "rgb.png", {0xFF00FF00u, 255}), std::runtime_error);  // all key
  EXPECT_THROW((void)readSilhouette(dir.path() / "none.png", {}), std::runtime_error);
}

}  // namespace
}  // namespace fieldcast::core
