// Moving entities drawn by the renderer's entity pass: where an entity appears is where its box
// projects (within a pixel); a ridge hides it; the nearer of two entities hides the farther,
// whatever their order; heading turns it; a control ray that meets it records its point.
#include "EntityPass.h"
#include "RenderTestUtil.h"

#include <ig_core/MemoryTerrain.h>
#include <ig_core/Renderer.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

namespace fieldcast::core::test {
namespace {

constexpr double kGroundM = 100.0;

// 256² voxels at 2 m, flat at 100 m; with a ridge 30 m high across y = 200 m when asked
std::unique_ptr<MemoryTerrain> flatLand(bool ridge) {
  constexpr int kSide = 256;
  TerrainGeometry g;
  g.widthVox = g.heightVox = kSide;
  g.spacingM = 2.0;
  g.heightStepM = 0.05;
  g.tileShift = 6;
  std::vector<std::uint16_t> heightQ(kSide * kSide, static_cast<std::uint16_t>(kGroundM / g.heightStepM));
  std::vector<std::uint32_t> colour(kSide * kSide, 0xFF3C7846u);
  if (ridge)
    for (int j = 99; j <= 101; ++j)
      for (int i = 0; i < kSide; ++i)
        heightQ[static_cast<std::size_t>(j * kSide + i)] = static_cast<std::uint16_t>(130.0 / g.heightStepM);
  return std::make_unique<MemoryTerrain>(g, heightQ, colour);
}

// A solid block of one colour, sx × sy × sz voxels
std::shared_ptr<const VoxelSolid> block(int sx, int sy, int sz, std::uint32_t rgba) {
  auto s = std::make_shared<VoxelSolid>(emptySolid(sx, sy, sz));
  std::fill(s->rgba.begin(), s->rgba.end(), rgba);
  return s;
}

EntityInstance entityAt(std::shared_ptr<const VoxelSolid> model, double x, double y, double headingDeg, double scale) {
  EntityInstance e;
  e.model = std::move(model);
  e.pose.positionM = {x, y, kGroundM};
  e.pose.headingRad = radians(headingDeg);
  e.scale = scale;
  return e;
}

// The camera 20 m up at (256, 40), looking north and 8° down
ViewRequest lookNorth(std::vector<EntityInstance> entities) {
  ViewRequest r;
  r.pose.positionM = {256.0, 40.0, kGroundM + 20.0};
  r.pose.pitchRad = radians(-8.0);
  r.display = Intrinsics::fromHorizontalFov(320, 240, radians(50.0));
  r.entities = std::move(entities);
  return r;
}

// The pixels where two frames differ: their count and bounding box (u0, v0, u1, v1 inclusive)
struct Changed {
  int count = 0;
  int u0 = 1 << 30, v0 = 1 << 30, u1 = -1, v1 = -1;
};
Changed changedPixels(const Frame& a, const Frame& b) {
  Changed c;
  const int bpp = a.image.format() == PixelFormat::Grey8 ? 1 : 3;
  for (int v = 0; v < a.intrinsics.heightPx; ++v)
    for (int u = 0; u < a.intrinsics.widthPx; ++u)
      if (std::memcmp(a.image.row(v) + bpp * u, b.image.row(v) + bpp * u, static_cast<std::size_t>(bpp)) != 0) {
        ++c.count;
        c.u0 = std::min(c.u0, u), c.u1 = std::max(c.u1, u), c.v0 = std::min(c.v0, v), c.v1 = std::max(c.v1, v);
      }
  return c;
}

TEST(EntityRender, AnEntityAppearsWhereItsBoxProjectsAndARidgeHidesIt) {
  const auto land = flatLand(false), ridged = flatLand(true);
  Renderer renderer(land->view(), RenderSettings{}, 2), behindRidge(ridged->view(), RenderSettings{}, 2);
  // A 4 × 4 × 4 block at scale 4 (8 m a side) 260 m ahead
  const EntityInstance cube = entityAt(block(4, 4, 4, 0xFF2020E0u), 256.0, 300.0, 0.0, 4.0);
  const Frame bare = renderer.render(lookNorth({}));
  const Frame with = renderer.render(lookNorth({cube}));
  const Changed c = changedPixels(bare, with);
  ASSERT_GT(c.count, 0);
  // The box's corners projected: the changed pixels' centres span the same rectangle within a pixel
  double uMin = 1e9, uMax = -1e9, vMin = 1e9, vMax = -1e9;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 corner{252.0 + ((k & 1) ? 8.0 : 0.0), 296.0 + ((k & 2) ? 8.0 : 0.0),
                            kGroundM + ((k & 4) ? 8.0 : 0.0)};
    const glm::dvec2 px = *projectPoint(with.pose, with.intrinsics, corner);
    uMin = std::min(uMin, px.x), uMax = std::max(uMax, px.x), vMin = std::min(vMin, px.y), vMax = std::max(vMax, px.y);
  }
  std::printf("entity pixels u %d..%d v %d..%d; its box projects to u %.2f..%.2f v %.2f..%.2f\n", c.u0, c.u1, c.v0,
              c.v1, uMin, uMax, vMin, vMax);
  EXPECT_NEAR(c.u0 + 0.5, uMin, 1.0);
  EXPECT_NEAR(c.u1 + 0.5, uMax, 1.0);
  EXPECT_NEAR(c.v0 + 0.5, vMin, 1.0);
  EXPECT_NEAR(c.v1 + 0.5, vMax, 1.0);
  // The range image holds the entity: its near face at y = 296 through the box's middle pixel
  const int u = (c.u0 + c.u1) / 2, v = (c.v0 + c.v1) / 2;
  const glm::dvec3 ray = pixelRay(with.pose, with.intrinsics, pixelCentre(u, v));
  const double expected = (296.0 - with.pose.positionM.y) / ray.y;
  EXPECT_NEAR(with.rangeM[static_cast<std::size_t>(v * with.intrinsics.widthPx + u)], expected, 0.01);

  // Behind a ridge 30 m high the same entity is hidden entirely
  const Frame ridgeBare = behindRidge.render(lookNorth({}));
  const Frame ridgeWith = behindRidge.render(lookNorth({cube}));
  EXPECT_EQ(changedPixels(ridgeBare, ridgeWith).count, 0);
}

TEST(EntityRender, TheNearerOfTwoEntitiesHidesTheFartherWhateverTheirOrder) {
  const auto land = flatLand(false);
  Renderer renderer(land->view(), RenderSettings{}, 2);
  const EntityInstance nearBlock = entityAt(block(4, 2, 20, 0xFF20C020u), 256.0, 200.0, 0.0, 2.0);  // 4 × 2 × 20 m
  const EntityInstance farBlock = entityAt(block(8, 2, 12, 0xFFC02020u), 256.0, 240.0, 0.0, 2.0);   // 8 × 2 × 12 m
  const Frame bare = renderer.render(lookNorth({}));
  const Frame nearOnly = renderer.render(lookNorth({nearBlock}));
  const Frame nearFirst = renderer.render(lookNorth({nearBlock, farBlock}));
  const Frame farFirst = renderer.render(lookNorth({farBlock, nearBlock}));
  EXPECT_EQ(changedPixels(nearFirst, farFirst).count, 0);  // the order does not matter
  // Where the near block is, both frames show it as it is alone; the far block shows around it
  const int w = bare.intrinsics.widthPx;
  int nearPixels = 0, differ = 0;
  for (int v = 0; v < bare.intrinsics.heightPx; ++v)
    for (int u = 0; u < w; ++u) {
      if (std::memcmp(bare.image.row(v) + 3 * u, nearOnly.image.row(v) + 3 * u, 3) == 0) continue;
      ++nearPixels;
      differ += std::memcmp(nearOnly.image.row(v) + 3 * u, nearFirst.image.row(v) + 3 * u, 3) != 0;
    }
  EXPECT_GT(nearPixels, 50);
  EXPECT_EQ(differ, 0);
  EXPECT_GT(changedPixels(nearOnly, nearFirst).count, 50);  // the far one's visible part
  // The far block alone covers pixels the near one takes: they do overlap
  const Frame farOnly = renderer.render(lookNorth({farBlock}));
  const Changed nearBox = changedPixels(bare, nearOnly), farBox = changedPixels(bare, farOnly);
  EXPECT_LT(farBox.u0, nearBox.u0);
  EXPECT_GT(farBox.u1, nearBox.u1);
  EXPECT_GT(farBox.v1, nearBox.v0);
}

TEST(EntityRender, HeadingTurnsTheModel) {
  const auto land = flatLand(false);
  Renderer renderer(land->view(), RenderSettings{}, 1);
  // Looking straight down from 120 m at a model 2 voxels wide and 10 long (scale 4: 4 × 20 m)
  const auto longModel = block(2, 10, 2, 0xFFE0E0E0u);
  ViewRequest r;
  r.pose.positionM = {256.0, 256.0, kGroundM + 120.0};
  r.pose.pitchRad = radians(-90.0);
  r.display = Intrinsics::fromHorizontalFov(240, 240, radians(40.0));
  const Frame bare = renderer.render(r);
  r.entities = {entityAt(longModel, 256.0, 256.0, 0.0, 4.0)};
  const Changed north = changedPixels(bare, renderer.render(r));
  r.entities = {entityAt(longModel, 256.0, 256.0, 90.0, 4.0)};
  const Changed east = changedPixels(bare, renderer.render(r));
  EXPECT_GT(north.v1 - north.v0, 3 * (north.u1 - north.u0));  // along the image's up (north)
  EXPECT_GT(east.u1 - east.u0, 3 * (east.v1 - east.v0));      // across it
}

TEST(EntityRender, HeadingIsClockwiseFromNorthAndTheModelsRightIsPlusX) {
  // A model 4 wide (x) and 8 long (y): its front half red, its back half blue, and a white marker
  // on its front right corner. Seen from straight above (image up north, right east) at heading
  // 90° its front points east (red on the right) and its right side south (the marker low right);
  // at 270° the front points west
  auto s = std::make_shared<VoxelSolid>(emptySolid(4, 8, 1));
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 4; ++x) s->rgba[s->index(x, y, 0)] = y >= 4 ? 0xFF2020E0u : 0xFFE02020u;
  s->rgba[s->index(3, 7, 0)] = 0xFFFFFFFFu;
  const auto land = flatLand(false);
  Renderer renderer(land->view(), RenderSettings{}, 1);
  ViewRequest r;
  r.pose.positionM = {256.0, 256.0, kGroundM + 100.0};
  r.pose.pitchRad = radians(-90.0);
  r.display = Intrinsics::fromHorizontalFov(200, 200, radians(40.0));
  // Where a colour is in the frame: the mean pixel of the pixels nearest to it
  const auto centreOf = [](const Frame& f, int channel) {
    double su = 0.0, sv = 0.0;
    int n = 0;
    for (int v = 0; v < f.intrinsics.heightPx; ++v)
      for (int u = 0; u < f.intrinsics.widthPx; ++u) {
        const std::uint8_t* p = f.image.row(v) + 3 * u;
        const bool white = p[0] > 200 && p[1] > 200 && p[2] > 200;
        const bool match = channel < 0 ? white
                                       : !white && p[channel] > 2 * p[(channel + 1) % 3] + 40 &&
                                             p[channel] > 2 * p[(channel + 2) % 3] + 40;
        if (match) su += u, sv += v, ++n;
      }
    return glm::dvec2(su / std::max(n, 1), sv / std::max(n, 1));
  };
  for (const double heading : {90.0, 270.0}) {
    r.entities = {entityAt(s, 256.0, 256.0, heading, 4.0)};  // 8 × 16 m
    const Frame f = renderer.render(r);
    const glm::dvec2 red = centreOf(f, 0), blue = centreOf(f, 2), marker = centreOf(f, -1);
    const double east = heading == 90.0 ? 1.0 : -1.0;      // where the front points along the image's u
    EXPECT_GT(east * (red.x - blue.x), 20.0) << heading;   // the front half ahead of the back half
    EXPECT_GT(east * (marker.y - red.y), 5.0) << heading;  // the right side south (down) at 90°, north at 270°
    EXPECT_GT(east * (marker.x - red.x), 5.0) << heading;  // the marker at the front
  }
}

TEST(EntityRender, AControlRayThatMeetsAnEntityRecordsItsPoint) {
  const auto land = flatLand(false);
  Renderer renderer(land->view(), RenderSettings{}, 1);
  // The middle control point looks 8° down from 20 m: it meets the ground about 142 m ahead. A
  // block 20 m tall (scale 2) 100 m ahead stands in its way
  const Frame bare = renderer.render(lookNorth({}));
  const Frame with = renderer.render(lookNorth({entityAt(block(20, 4, 20, 0xFF808080u), 256.0, 140.0, 0.0, 2.0)}));
  const ControlPoint& before = bare.controlPoints[4];
  const ControlPoint& after = with.controlPoints[4];
  ASSERT_EQ(after.kind, ControlPointKind::Surface);
  EXPECT_NEAR(before.world.z, kGroundM, 0.5);
  EXPECT_NEAR(after.world.y, 138.0, 0.01);  // the block's near face (4 voxels of 1 m deep about y = 140)
  EXPECT_GT(after.world.z, kGroundM + 1.0);
  EXPECT_EQ(bare.controlPoints[0].world, with.controlPoints[0].world);  // a corner's ray misses it
}

TEST(EntityRender, ABoxReachingBehindTheEyeCoversOnlyItsSideOfTheScreen) {
  // A wall 4 m to the camera's left, from 30 m behind it to 60 m ahead: its box is clipped to the
  // near plane, so it covers the left of the screen only — and every pixel whose ray meets the
  // wall (found by casting every pixel of the frame) lies in it and is drawn.
  const auto terrain = flatLand(false);
  const auto wall = block(4, 180, 20, 0xFF2020E0u);  // 2 × 90 × 10 m at 0.5 m voxels
  EntityInstance e = entityAt(wall, 256.0 - 5.0, 40.0 + 15.0, 0.0, 1.0);
  const ViewRequest r = lookNorth({e});
  RenderSettings settings;
  settings.rangeImage = true;
  Renderer renderer(terrain->view(), settings, 2);
  const Frame with = renderer.render(r);
  const ViewGeometry geo(with.pose, with.intrinsics, terrain->geometry(), settings);
  const PixelBox box = entityScreenBox(e, geo);
  EXPECT_EQ(box.u0, 0);
  EXPECT_LT(box.u1, with.intrinsics.widthPx / 2);  // the left half at most: not the whole frame
  int meets = 0, outside = 0, notDrawn = 0;
  for (int v = 0; v < with.intrinsics.heightPx; ++v)
    for (int u = 0; u < with.intrinsics.widthPx; ++u) {
      EntityHit hit;
      if (!castEntity(e, with.pose.positionM, geo.ray(u + 0.5, v + 0.5), 1e9, hit)) continue;
      ++meets;
      outside += u < box.u0 || u >= box.u1 || v < box.v0 || v >= box.v1;
      const std::uint8_t* p = with.image.row(v) + 3 * u;
      notDrawn += !(p[0] > 100 && p[0] > 3 * p[1]);  // the wall's red (its east face in the sky's light)
    }
  EXPECT_GT(meets, 2000);
  EXPECT_EQ(outside, 0);
  EXPECT_EQ(notDrawn, 0);
}

TEST(EntityRender, TheReferenceRendererDrawsTheEntitiesAsTheEntityPassDoes) {
  // Four entities seen from 20 m up, 8° down: a block, a two-coloured model turned 30° and at
  // scale 2, one half hidden behind the ridge, and the wall reaching behind the eye. The
  // reference renderer marches each pixel's ray through each model on its own (1/32-voxel
  // samples); the entity pass walks the grid. They must draw the same pixels in the same colours.
  const auto land = flatLand(true);
  auto twoTone = std::make_shared<VoxelSolid>(emptySolid(6, 10, 6));
  for (int z = 0; z < 6; ++z)
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 6; ++x)
        if (z < 3 || (x > 0 && x < 5 && y > 2 && y < 8))  // a body and a cabin
          twoTone->rgba[twoTone->index(x, y, z)] = y >= 5 ? 0xFF2020E0u : 0xFFE08020u;
  const std::vector<EntityInstance> entities{
      entityAt(block(8, 8, 12, 0xFF20C0E0u), 230.0, 120.0, 0.0, 2.0), entityAt(twoTone, 280.0, 100.0, 30.0, 2.0),
      entityAt(block(10, 6, 40, 0xFFE0E020u), 256.0, 206.0, 15.0, 2.0),  // behind the ridge at y = 200 m
      entityAt(block(4, 180, 20, 0xFF2020E0u), 251.0, 55.0, 0.0, 1.0),   // beside and behind the eye
  };
  RenderSettings settings;
  Renderer renderer(land->view(), settings, 2);
  const ReferenceRenderer reference(land->view());
  const ViewRequest bare = lookNorth({});
  const ViewRequest with = lookNorth(entities);
  const Frame fastBare = renderer.render(bare), fastWith = renderer.render(with);
  const Frame refBare = reference.render(bare, settings), refWith = reference.render(with, settings);
  const auto differs = [](const Frame& a, const Frame& b, int u, int v, int by) {
    const std::uint8_t* p = a.image.row(v) + 3 * u;
    const std::uint8_t* q = b.image.row(v) + 3 * u;
    return std::abs(p[0] - q[0]) > by || std::abs(p[1] - q[1]) > by || std::abs(p[2] - q[2]) > by;
  };
  int either = 0, onlyOne = 0, both = 0, colourOff = 0;
  for (int v = 0; v < fastWith.intrinsics.heightPx; ++v)
    for (int u = 0; u < fastWith.intrinsics.widthPx; ++u) {
      const bool inFast = differs(fastWith, fastBare, u, v, 0);
      const bool inRef = differs(refWith, refBare, u, v, 0);
      either += inFast || inRef;
      onlyOne += inFast != inRef;
      if (inFast && inRef) {
        ++both;
        colourOff += differs(fastWith, refWith, u, v, 2);
      }
    }
  std::printf("entity pixels: %d in either renderer, %d in one only, %d of %d both-drawn off by > 2\n", either, onlyOne,
              colourOff, both);
  EXPECT_GT(either, 10000);
  EXPECT_LE(onlyOne, either / 200);  // 99.5% the same pixels (a ray grazing a voxel's edge may differ)
  EXPECT_LE(colourOff, both / 200);
  // ... and the range image and control points see them alike
  int rangeOff = 0;
  for (std::size_t k = 0; k < fastWith.rangeM.size(); ++k)
    rangeOff += std::abs(fastWith.rangeM[k] - refWith.rangeM[k]) > 0.01f * refWith.rangeM[k] + 0.05f;
  EXPECT_LE(rangeOff, static_cast<int>(fastWith.rangeM.size()) / 100);
  for (std::size_t k = 0; k < fastWith.controlPoints.size(); ++k)
    EXPECT_LT(glm::length(fastWith.controlPoints[k].world - refWith.controlPoints[k].world), 0.5) << k;
}

}  // namespace
}  // namespace fieldcast::core::test
