// The fast column caster judged by the plain reference renderer over a sweep of poses.
#include "RenderTestUtil.h"

#include <ig_core/Renderer.h>
#include <ig_core/VoxelSolid.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace fieldcast::core::test {
namespace {

struct SweepPose {
  double headingDeg, pitchDeg, altitudeM, fovDeg;
  int displayWidthPx = 80;
  double rollDeg = 0.0;  ///< a rolled frame renders only its footprint (FrameFootprint)
};

// Heading all round, pitch −2°..−89°, altitude 20 m..5 km, field of view 20°..90°; the diagonals;
// and three banked poses.
std::vector<SweepPose> sweep() {
  const std::array<double, 8> pitches{-2, -5, -10, -20, -35, -55, -75, -89};
  const std::array<double, 6> altitudes{20, 60, 200, 700, 2000, 5000};
  const std::array<double, 4> fovs{20, 45, 70, 90};
  std::vector<SweepPose> poses;
  for (int k = 0; k < 24; ++k) {
    poses.push_back({std::fmod(17.0 + k * 137.5, 360.0), pitches[static_cast<std::size_t>(k % 8)],
                     altitudes[static_cast<std::size_t>((k * 5) % 6)], fovs[static_cast<std::size_t>((k * 3) % 4)]});
  }
  // Along the grid diagonals, where the columns' major axis changes (DiagonalSeam): an 81-pixel
  // display's centre column looks exactly along the heading.
  poses.push_back({45.0, -8.0, 20.0, 70.0, 81});
  poses.push_back({135.0, -20.0, 60.0, 45.0, 81});
  poses.push_back({225.0, -35.0, 200.0, 90.0, 81});
  poses.push_back({315.0, -5.0, 20.0, 20.0, 81});
  poses.push_back({44.99, -12.0, 60.0, 45.0, 81});
  // Banked: the frame grows to the turned window's bounding box and renders the turned window
  poses.push_back({70.0, -10.0, 60.0, 70.0, 80, 35.0});
  poses.push_back({250.0, -25.0, 200.0, 45.0, 80, -60.0});
  poses.push_back({160.0, -5.0, 20.0, 90.0, 80, 120.0});
  return poses;
}

// How close the two renderers must come: per pose and overall, the share of pixels on the
// reference's voxel or a neighbour; and the largest voxel distance of a control point's hit.
struct Agreement {
  double perPose = 0.995, overall = 0.995;
  int controlPointVoxels = 1;
};

void sweepAgainstTheReference(const TerrainView& view, double maxAnisotropy, const Agreement& bound = {},
                              const std::vector<EntityInstance>& entities = {}, bool laneMarch = false) {
  RenderSettings settings;
  settings.rangeImage = true;
  settings.maxAnisotropy = maxAnisotropy;
  settings.laneMarch = laneMarch;
  Renderer renderer(view, settings, 2);
  const ReferenceRenderer reference(view);
  int total = 0;
  int same = 0;
  int entityPixels = 0;  // pixels the entities change in the fast frames
  std::uint64_t secondaryRays = 0;
  for (const SweepPose& s : sweep()) {
    ViewRequest request;
    request.pose = poseAbove(view, 420.0, 380.0, s.altitudeM, s.headingDeg, s.pitchDeg);
    request.pose.rollRad = radians(s.rollDeg);
    request.display = Intrinsics::fromHorizontalFov(s.displayWidthPx, 60, radians(s.fovDeg));
    request.entities = entities;
    RenderStats stats;
    const Frame fast = renderer.render(request, &stats);
    secondaryRays += stats.secondaryRays;
    const Frame ref = reference.render(request, settings);
    const HitAgreement a = compareHits(fast, ref, view.geometry(), settings);
    if (!entities.empty()) {
      ViewRequest bare = request;
      bare.entities.clear();
      const Frame without = renderer.render(bare);
      for (std::size_t k = 0; k < fast.rangeM.size(); ++k) entityPixels += fast.rangeM[k] != without.rangeM[k];
    }
    std::printf(
        "heading %6.1f pitch %6.1f roll %6.1f alt %6.0f fov %4.0f: %.4f same (%d sky mismatches, %d at the edge)\n",
        s.headingDeg, s.pitchDeg, s.rollDeg, s.altitudeM, s.fovDeg, a.fraction(), a.skyMismatch, a.atEdge);
    EXPECT_GE(a.fraction(), bound.perPose)
        << "pose heading " << s.headingDeg << " pitch " << s.pitchDeg << " roll " << s.rollDeg;
    total += a.pixels;
    same += a.same;
    // Control points: within bound.controlPointVoxels (at the level used) of the reference's
    // (its own ray's hit on the terrain, or on an entity in front of it).
    const ViewGeometry geo(fast.pose, fast.intrinsics, view.geometry(), settings);
    ASSERT_EQ(fast.controlPoints.size(), ref.controlPoints.size());
    for (std::size_t k = 0; k < fast.controlPoints.size(); ++k) {
      const ControlPoint& cp = fast.controlPoints[k];
      const ControlPoint& rc = ref.controlPoints[k];
      ASSERT_EQ(cp.kind, rc.kind) << "control point at " << cp.framePx.x << "," << cp.framePx.y;
      if (cp.kind != ControlPointKind::Surface) continue;
      const int level = geo.lodLevel(glm::dot(cp.world - fast.pose.positionM, geo.axes().forward),
                                     geo.ray(cp.framePx.x, cp.framePx.y));
      EXPECT_LE(voxelDistance(view.geometry(), cp.world, rc.world, level), bound.controlPointVoxels);
    }
  }
  const double overall = static_cast<double>(same) / total;
  std::printf("overall: %.5f of %d pixels hit the reference voxel or a neighbour; %llu secondary rays\n", overall,
              total, static_cast<unsigned long long>(secondaryRays));
  if (view.sticks() != nullptr && view.sticks()->hasSeeThrough()) {
    EXPECT_GT(secondaryRays, 0u) << "no pose sees through the complex sticks";
  }
  EXPECT_GE(overall, bound.overall);
  if (!entities.empty()) {
    std::printf("%d pixels show entities\n", entityPixels);
    EXPECT_GT(entityPixels, 500) << "the entities are not in view";
  }
}

TEST(RenderAccuracy, ColumnCasterHitsTheReferenceVoxelOverAPoseSweep) { sweepAgainstTheReference(hills().view(), 0.0); }

// The grazing-angle level of detail changes the surface both renderers see; they must still agree.
TEST(RenderAccuracy, GrazingAngleLevelOfDetailAgreesWithTheReference) { sweepAgainstTheReference(hills().view(), 2.0); }

// The same hills furnished with woods and a village of sticks. A stick raises one voxel's height
// sample by up to 30 m, and on such steep one-voxel leans the two renderers' surfaces part more
// than on terrain: the reference's is bilinear over each cell, the caster's linear along grid
// lines and ruled between them. A pitched camera's column planes are tilted, and a stick can rise
// above a grid line's line in the plane past the crossing the march takes; where a voxel spans
// 8 pixels or more the rows that see it are cast ray by ray (pieceBeyondCrossing): the pose 20 m
// above the church tower, 75° down, went from 94.85% to 98.63%. Measured (2026-12-05): overall
// 99.628%, eight poses under 99.5%, the worst 97.38% (a wood seen along the diagonal, 60 m up,
// 20° down: single trees' leans). The bounds are a guard against losing more.
TEST(RenderAccuracy, ColumnCasterHitsTheReferenceVoxelOverHillsWithObjects) {
  sweepAgainstTheReference(furnishedHills().view(), 0.0, Agreement{0.97, 0.995, 8});
}

// Entities among the objects: eight vehicles on the ground around the sweep's point, facing every
// way, and a block in the air over it. The entity pass and the reference's own march through each
// model must hit the same voxels (EntityRender compares their colours).
std::vector<EntityInstance> vehiclesAround(const TerrainView& view) {
  auto vehicle = std::make_shared<VoxelSolid>(emptySolid(4, 10, 5));  // 2 × 5 × 2.5 m at scale 1
  for (int z = 0; z < 5; ++z)
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 4; ++x)
        if (z >= 1 || y < 2 || y > 7) vehicle->rgba[vehicle->index(x, y, z)] = z == 4 ? 0xFFE0E0E0u : 0xFF2030C0u;
  std::vector<EntityInstance> entities;
  for (int k = 0; k < 8; ++k) {
    const double bearing = radians(45.0 * k + 10.0), distanceM = 25.0 + 15.0 * k;
    EntityInstance e;
    e.id = static_cast<std::uint32_t>(k + 1);
    e.model = vehicle;
    e.pose.positionM = {420.0 + distanceM * std::sin(bearing), 380.0 + distanceM * std::cos(bearing), 0.0};
    e.pose.positionM.z = view.heightAtM(e.pose.positionM.x, e.pose.positionM.y);
    e.pose.headingRad = radians(37.0 * k);
    e.scale = 1.5;
    entities.push_back(e);
  }
  EntityInstance high;
  high.id = 9;
  high.model = vehicle;
  high.pose.positionM = {430.0, 370.0, view.heightAtM(430.0, 370.0) + 60.0};
  high.pose.pitchRad = radians(20.0);
  high.scale = 4.0;
  entities.push_back(high);
  return entities;
}

TEST(RenderAccuracy, ColumnCasterHitsTheReferenceVoxelOverHillsWithObjectsAndEntities) {
  const TerrainView& view = furnishedHills().view();
  sweepAgainstTheReference(view, 0.0, Agreement{0.97, 0.995, 8}, vehiclesAround(view));
}

// The lane march (neighbouring columns in step) over the same sweeps.
TEST(RenderAccuracy, LaneMarchHitsTheReferenceVoxelOverAPoseSweep) {
  sweepAgainstTheReference(hills().view(), 0.0, {}, {}, true);
}

TEST(RenderAccuracy, LaneMarchWithGrazingAngleLevelOfDetailAgreesWithTheReference) {
  sweepAgainstTheReference(hills().view(), 2.0, {}, {}, true);
}

// Measured (2026-12-05): overall 99.566%, the worst pose 96.80% (the same wood along the diagonal).
TEST(RenderAccuracy, LaneMarchHitsTheReferenceVoxelOverHillsWithObjects) {
  sweepAgainstTheReference(furnishedHills().view(), 0.0, Agreement{0.96, 0.995, 8}, {}, true);
}

}  // namespace
}  // namespace fieldcast::core::test
