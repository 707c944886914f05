// The scene's scripted entities posed for a frame: on the flight's clock, a ground vehicle on the
// terrain under it and level, an aircraft where its waypoints put it; a model that cannot be read
// is named with its entity.
#include "SceneEntities.h"

#include <ig_core/SyntheticTerrain.h>
#include <ig_core/VoxFile.h>

#include <fieldcast/Conventions.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <vector>

namespace fieldcast::app {
namespace {

motion::ScriptedEntity scripted(const std::string& name, const std::filesystem::path& model, bool onGround,
                                glm::dvec3 from, glm::dvec3 to) {
  std::vector<motion::Waypoint> w(2);
  w[0].timeS = 0.0, w[0].positionM = from;
  w[1].timeS = 10.0, w[1].positionM = to;
  return {name, model, 1.0, onGround, motion::ScriptedTrajectory(name, w, 0.0, motion::FlightEnd::Hold, 0.0)};
}

TEST(SceneEntities, PosesEachEntityOnTheFlightsClock) {
  const auto dir = std::filesystem::temp_directory_path() / "fieldcast_scene_entities";
  std::filesystem::create_directories(dir);
  core::VoxelSolid box = core::emptySolid(2, 4, 2);
  std::fill(box.rgba.begin(), box.rgba.end(), 0xFF8080FFu);
  core::writeVoxFile(dir / "box.vox", box);
  const auto hills = core::makeSyntheticTerrain({core::SyntheticKind::Hills, 256, 2.0, 6, 3});
  const core::TerrainView& ground = hills->view();
  // The flight's time 0 is at 100 s
  const TimePoint start{std::chrono::seconds(100)};
  SceneEntities scene({scripted("van", dir / "box.vox", true, {100, 100, 0}, {300, 100, 0}),
                       scripted("plane", dir / "box.vox", false, {0, 400, 500}, {0, 200, 500})},
                      &ground, [start](TimePoint t) { return toSeconds(t - start); });
  std::vector<core::EntityInstance> out(7);  // cleared first
  scene.at(start + std::chrono::seconds(5), out);
  ASSERT_EQ(out.size(), 2u);
  const core::EntityInstance& van = out[0];
  EXPECT_NEAR(van.pose.positionM.x, 200.0, 1e-9);
  EXPECT_NEAR(van.pose.positionM.z, ground.heightAtM(200.0, 100.0), 1e-9);  // on the ground
  EXPECT_GT(van.pose.positionM.z, 1.0);
  EXPECT_NEAR(van.pose.headingRad, radians(90.0), 1e-9);  // east, along its track
  EXPECT_EQ(van.pose.pitchRad, 0.0);
  EXPECT_EQ(van.pose.rollRad, 0.0);
  ASSERT_TRUE(van.model);
  EXPECT_EQ(van.model->sizeY, 4);
  const core::EntityInstance& plane = out[1];
  EXPECT_NEAR(plane.pose.positionM.y, 300.0, 1e-9);
  EXPECT_NEAR(plane.pose.positionM.z, 500.0, 1e-9);  // where its waypoints say
  EXPECT_NEAR(std::abs(plane.pose.headingRad), radians(180.0), 1e-9);
  EXPECT_NE(van.id, plane.id);

  try {
    SceneEntities broken({scripted("lorry", dir / "lorry.vox", true, {0, 0, 0}, {1, 1, 0})}, &ground,
                         [](TimePoint) { return 0.0; });
    ADD_FAILURE() << "a missing model was taken";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("entity 'lorry': " + (dir / "lorry.vox").string() + ": cannot open"),
              std::string::npos)
        << e.what();
  }
}

TEST(HostEntityPose, AnAttachedEntityRidesItsParentAtItsOffset) {
  // A tanker (entity 5) heading east at 100 m/s; a drogue (6) attached 30 m behind it and 5 m
  // below, turned 10° right; a pod (7) 2 m to the right of the drogue; a wingman (8) attached to
  // the ownship 50 m to its left.
  const TimePoint t0{std::chrono::seconds(10)};
  HostEntitySample tanker;
  tanker.id = 5;
  tanker.pose = Pose{{1000.0, 2000.0, 3000.0}, radians(90.0), 0.0, 0.0};
  tanker.velocityMps = {100.0, 0.0, 0.0};
  tanker.at = t0;
  HostEntitySample drogue;
  drogue.id = 6;
  drogue.attached = true;
  drogue.parentId = 5;
  drogue.offset = ViewOffset{{0.0, -30.0, -5.0}, radians(10.0), 0.0, 0.0};
  HostEntitySample pod;
  pod.id = 7;
  pod.attached = true;
  pod.parentId = 6;
  pod.offset = ViewOffset{{2.0, 0.0, 0.0}, 0.0, 0.0, 0.0};
  HostEntitySample wingman;
  wingman.id = 8;
  wingman.attached = true;
  wingman.parentId = 0;
  wingman.offset = ViewOffset{{-50.0, 0.0, 0.0}, 0.0, 0.0, 0.0};
  const std::vector<HostEntitySample> all{tanker, drogue, pod, wingman};
  const FindHostEntity find = [&all](std::uint16_t id) -> const HostEntitySample* {
    for (const HostEntitySample& s : all)
      if (s.id == id) return &s;
    return nullptr;
  };
  const OwnshipPose ownship = [](TimePoint) { return Pose{{0.0, 0.0, 500.0}, radians(180.0), 0.0, 0.0}; };

  const TimePoint t = t0 + std::chrono::milliseconds(200);  // the tanker has flown 20 m east
  const Pose d = *hostEntityPose(drogue, t, ownship, find);
  EXPECT_NEAR(d.positionM.x, 1000.0 + 20.0 - 30.0, 1e-9);
  EXPECT_NEAR(d.positionM.y, 2000.0, 1e-9);
  EXPECT_NEAR(d.positionM.z, 3000.0 - 5.0, 1e-9);
  EXPECT_NEAR(d.headingRad, radians(100.0), 1e-9);
  const Pose p = *hostEntityPose(pod, t, ownship, find);  // 2 m right of the drogue, heading 100°
  EXPECT_NEAR(p.positionM.x, d.positionM.x + 2.0 * std::cos(radians(100.0)), 1e-9);  // right: (cos ψ, −sin ψ)
  EXPECT_NEAR(p.positionM.y, d.positionM.y - 2.0 * std::sin(radians(100.0)), 1e-9);
  const Pose w = *hostEntityPose(wingman, t, ownship, find);  // the ownship heads south: its left is east
  EXPECT_NEAR(w.positionM.x, 50.0, 1e-9);
  EXPECT_NEAR(w.positionM.y, 0.0, 1e-9);

  EXPECT_FALSE(hostEntityPose(wingman, t, {}, find));  // no ownship pose given
  HostEntitySample orphan = pod;
  orphan.parentId = 99;
  EXPECT_FALSE(hostEntityPose(orphan, t, ownship, find));
  std::vector<HostEntitySample> loop{drogue, pod};
  loop[0].parentId = 7;  // 6 on 7, 7 on 6
  const FindHostEntity findInLoop = [&loop](std::uint16_t id) -> const HostEntitySample* {
    return id == 6 ? &loop[0] : id == 7 ? &loop[1] : nullptr;
  };
  EXPECT_FALSE(hostEntityPose(loop[1], t, ownship, findInLoop));
}

}  // namespace
}  // namespace fieldcast::app
