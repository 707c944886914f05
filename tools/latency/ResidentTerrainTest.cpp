// `fieldcast-latency --db`: the database loaded whole (a frame over it reads no coarser level in
// place of a tile, where the service's paged cache, freshly opened, does), a budget too small
// refused with the budget it would need, and a flight that leaves the terrain named.
#include "ResidentTerrain.h"

#include <ig_core/BuiltinTerrain.h>
#include <ig_core/OpenTerrain.h>
#include <ig_core/Renderer.h>

#include <fieldcast/Conventions.h>

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

namespace fieldcast::tools {
namespace {

namespace fs = std::filesystem;

class ResidentTerrain : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = fs::temp_directory_path() / ("fieldcast_resident_" + std::to_string(::getpid()));
    // 1024² voxels at 2 m: three levels, 16 + 4 + 1 tiles
    sDatabase = core::ensureBuiltinDatabase(sDir, {1024, 2.0, 1}, [](std::string_view, double) {});
  }
  static void TearDownTestSuite() { fs::remove_all(sDir); }

  // Samples a coarser level stood in for while a frame over the middle of the terrain was cast
  static std::uint64_t missesOfOneFrame(const core::TerrainView& view) {
    core::Renderer renderer(view, core::RenderSettings{}, 1);
    core::ViewRequest request;
    request.pose.positionM = {1024.0, 300.0, view.heightAtM(1024.0, 300.0) + 120.0};
    request.pose.pitchRad = radians(-15.0);
    request.display = Intrinsics::fromHorizontalFov(160, 120, radians(60.0));
    const std::uint64_t before = view.missCount();
    renderer.render(request);
    return view.missCount() - before;
  }

  static inline fs::path sDir, sDatabase;
};

TEST_F(ResidentTerrain, HoldsEveryTileSoAFrameReadsNoStandIn) {
  const auto cache = openResidentDatabase(sDatabase, std::size_t{64} << 20);
  EXPECT_EQ(cache->stats().residentTiles, 21u);
  EXPECT_EQ(missesOfOneFrame(cache->view()), 0u);
  // A paged cache as the service opens it holds only the coarse levels that fit its pinned share
  // (a quarter of the budget: here the top level alone) until the camera asks for more: the
  // same frame reads stand-ins
  const auto paged = core::openTerrain(sDatabase.string(), {}, std::size_t{4} << 20);
  EXPECT_GT(missesOfOneFrame(paged->view()), 0u);
}

TEST_F(ResidentTerrain, RefusesABudgetTooSmallNamingWhatItNeeds) {
  try {
    openResidentDatabase(sDatabase, std::size_t{2} << 20);
    FAIL() << "a 2 MB budget held the whole database";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("do not fit in --db-budget-mb 2 (about "), std::string::npos) << e.what();
  }
  EXPECT_THROW(openResidentDatabase(sDir / "missing.fctdb", std::size_t{64} << 20), std::runtime_error);
}

TEST_F(ResidentTerrain, NamesWhereAFlightLeavesTheTerrain) {
  core::TerrainGeometry grid;
  grid.widthVox = grid.heightVox = 1024;  // x, y from −1 to 2047 m
  EvaluationSpec spec;
  spec.startS = 1.0;
  spec.fields = 60;  // flight time 0 to 2 s
  const EvaluatedFlight eastward("eastward", 10.0, [](double t) {
    Pose p;
    p.positionM = {1900.0 + 100.0 * t, 1000.0, 300.0};
    return p;
  });
  const std::optional<std::string> outside = whereFlightLeavesTerrain(eastward, grid, spec);
  ASSERT_TRUE(outside.has_value());
  EXPECT_NE(outside->find("flight 'eastward' is at (2048.0, 1000.0) at 1.48 s, outside"), std::string::npos)
      << *outside;
  spec.startS = 0.2;
  spec.fields = 30;  // up to 0.7 s: x ≤ 1970 m
  EXPECT_FALSE(whereFlightLeavesTerrain(eastward, grid, spec).has_value());
}

}  // namespace
}  // namespace fieldcast::tools
