// Placing voxel models as sticks: a thousand copies share the table's entries, heading and scale
// turn and size the footprint, a model stands on the lowest ground under it, and the placement
// list says what is wrong with it, line by line.
#include "TerrainTestUtil.h"

#include <ig_core/ObjectPlacement.h>

#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <utility>

namespace fieldcast::core {
namespace {

using testing::ScratchDir;

// A flat grid of side × side voxels at 2 m, ground at 100 m (step 5 cm), without sticks
TerrainGrid flatGrid(int side) {
  TerrainGrid grid;
  grid.geometry.widthVox = grid.geometry.heightVox = side;
  grid.geometry.spacingM = 2.0;
  grid.geometry.heightStepM = 0.05;
  grid.heightQ.assign(static_cast<std::size_t>(side * side), 2000);
  grid.colourRgba.assign(static_cast<std::size_t>(side * side), 0xFF336633u);
  return grid;
}

// The extent (voxels) of the sticks in `grid`: i0, i1, j0, j1
std::array<int, 4> stickExtent(const TerrainGrid& grid) {
  std::array<int, 4> e{1 << 30, -1, 1 << 30, -1};
  const int w = grid.geometry.widthVox;
  for (std::size_t k = 0; k < grid.stickId.size(); ++k) {
    if (grid.stickId[k] == 0) continue;
    const int i = static_cast<int>(k) % w, j = static_cast<int>(k) / w;
    e = {std::min(e[0], i), std::max(e[1], i), std::min(e[2], j), std::max(e[3], j)};
  }
  return e;
}

TEST(ObjectPlacement, AThousandHousesShareTheTablesEntries) {
  TerrainGrid grid = flatGrid(1024);
  std::vector<ObjectPlacement> village;
  for (int k = 0; k < 1000; ++k) village.push_back({"house", 20.0 + 60.0 * (k % 32), 20.0 + 60.0 * (k / 32), 0.0, 1.0});
  const PlacementReport report = placeObjects(grid, village);
  const VoxelModel& house = *findBuiltinModel("house");
  std::set<std::uint32_t> used;
  for (const VoxelModel::Column& c : house.columns) used.insert(c.stick);
  EXPECT_EQ(report.placed, 1000u);
  EXPECT_EQ(report.tableEntries, used.size()) << "each kind of stick once, however many houses";
  EXPECT_EQ(grid.sticks->size(), used.size());
  EXPECT_EQ(report.stickVoxels, 1000u * house.columns.size());
}

TEST(ObjectPlacement, ATreesCavityUnderItsCrownReachesTheGroundAtAnyScaleOrSlope) {
  // The broadleaf's eight columns around its trunk (20 or 16 units of 0.5 m, the lowest 4 a
  // cavity: a fifth or a quarter) placed at scales 1.25 and 0.75 on flat ground, and at scales 1
  // and 0.8 on ground rising 1 m a voxel eastward: each complex stick reaches its own voxel's
  // ground, stretched or squeezed, its cavity at its foot in proportion.
  const auto check = [](double scale, bool slope) {
    const std::string what = "scale " + std::to_string(scale) + (slope ? " on the slope" : "");
    TerrainGrid grid = flatGrid(64);
    if (slope)
      for (std::size_t k = 0; k < grid.heightQ.size(); ++k)
        grid.heightQ[k] = static_cast<std::uint16_t>(2000 + 20 * (k % 64));
    placeObjects(grid, std::vector<ObjectPlacement>{{"broadleaf", 65.0, 65.0, 0.0, scale}});
    int complexColumns = 0;
    for (std::size_t k = 0; k < grid.stickId.size(); ++k) {
      const std::uint32_t id = grid.stickId[k];
      if (id == 0 || grid.sticks->entry(id).kind != StickKind::Complex) continue;
      ++complexColumns;
      const StickEntry& e = grid.sticks->entry(id);
      const double aboveGroundM = (grid.heightQ[k] - grid.groundQ[k]) * grid.geometry.heightStepM;
      EXPECT_NEAR(e.lengthVox * kModelStickUnitM, aboveGroundM, 0.25) << what;
      int cavity = 0;
      while (cavity < static_cast<int>(e.lengthVox) && e.texels[e.lengthVox - 1 - cavity] >> 24 == 0) ++cavity;
      EXPECT_GE(cavity, 1) << what << ": no cavity at the stick's foot";
      EXPECT_GE(cavity, e.lengthVox / 5.0 - 1.0) << what;
      EXPECT_LE(cavity, e.lengthVox / 4.0 + 1.0) << what;
      EXPECT_EQ(e.texels.front() >> 24, 0xFFu) << what << ": the crown is not on top";
      EXPECT_EQ(grid.colourRgba[k], 0xFF336633u) << "the voxel under a complex stick keeps the ground's colour";
    }
    EXPECT_GE(complexColumns, 4) << what;
  };
  check(1.25, false);
  check(0.75, false);
  check(1.0, true);
  check(0.8, true);
}

TEST(ObjectPlacement, HeadingTurnsAndScaleSizesTheFootprint) {
  // The house: 5 × 4 cells of 2 m, 10 m east-west and 8 m north-south at heading 0
  const auto extentOf = [](double heading, double scale) {
    TerrainGrid grid = flatGrid(128);
    const ObjectPlacement one{"house", 128.0, 128.0, heading, scale};
    placeObjects(grid, std::span(&one, 1));
    const auto e = stickExtent(grid);
    return std::pair{e[1] - e[0] + 1, e[3] - e[2] + 1};  // voxels along x, along y
  };
  EXPECT_EQ(extentOf(0.0, 1.0), std::pair(5, 4));
  EXPECT_EQ(extentOf(90.0, 1.0), std::pair(4, 5));
  EXPECT_EQ(extentOf(0.0, 2.0), std::pair(10, 8));
  // Scale is vertical too: the ridge twice as high above the ground
  TerrainGrid once = flatGrid(128), twice = flatGrid(128);
  const ObjectPlacement a{"house", 128.0, 128.0, 0.0, 1.0}, b{"house", 128.0, 128.0, 0.0, 2.0};
  placeObjects(once, std::span(&a, 1));
  placeObjects(twice, std::span(&b, 1));
  const auto top = [](const TerrainGrid& g) { return *std::max_element(g.heightQ.begin(), g.heightQ.end()) - 2000; };
  EXPECT_NEAR(top(twice), 2 * top(once), 1);
}

TEST(ObjectPlacement, AModelStandsOnTheLowestGroundUnderIt) {
  // Ground rising 1 m per voxel eastward: the house's walls reach down to its lowest corner, and
  // its roof is level (every eave column at the same height)
  TerrainGrid grid = flatGrid(64);
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i)
      grid.heightQ[static_cast<std::size_t>(j * 64 + i)] = static_cast<std::uint16_t>(2000 + 20 * i);
  const ObjectPlacement one{"house", 64.0, 64.0, 0.0, 1.0};
  placeObjects(grid, std::span(&one, 1));
  const auto e = stickExtent(grid);
  const auto at = [&](int i, int j) { return grid.heightQ[static_cast<std::size_t>(j * 64 + i)]; };
  for (int i = e[0]; i <= e[1]; ++i) EXPECT_EQ(at(i, e[2]), at(e[0], e[2])) << "eave column " << i;
  // The south row's top stands its height over the lowest ground (the west column)
  const int southUnits = findBuiltinModel("house")->columns[0].heightUnits;
  EXPECT_EQ(at(e[0], e[2]) - (2000 + 20 * e[0]), southUnits * kModelStickUnitM / 0.05);
}

TEST(ObjectPlacement, AModelPlacedAmongObjectsStandsOnTheirGroundNotOnThem) {
  // A hedge on every voxel (as a generator furnishes a terrain), then a house from a second list:
  // its south row stands its height over the ground, not over the hedges
  TerrainGrid grid = flatGrid(64);
  std::vector<ObjectPlacement> hedges;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) hedges.push_back({"hedge", i * 2.0, j * 2.0, 0.0, 1.0});
  placeObjects(grid, hedges);
  const std::vector<ObjectPlacement> house{{"house", 64.0, 64.0, 0.0, 1.0}};
  placeObjects(grid, house);
  const int southUnits = findBuiltinModel("house")->columns[0].heightUnits;
  std::set<std::uint32_t> houseTops;
  for (std::size_t k = 0; k < grid.heightQ.size(); ++k) houseTops.insert(grid.heightQ[k]);
  EXPECT_TRUE(houseTops.count(static_cast<std::uint32_t>(2000 + southUnits * kModelStickUnitM / 0.05)))
      << "the house's south row is not " << southUnits * kModelStickUnitM << " m over the ground";
  EXPECT_THROW(placeObjects(grid, std::vector<ObjectPlacement>{{"house", 1e12, 0.0, 0.0, 1.0}}), std::invalid_argument);
}

// Every built-in model, crowded so that objects overlap, on rough ground (complex sticks of
// many lengths), with random headings and scales
std::vector<PlacementRequest> crowdedRequests(std::size_t count) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> along(-10.0, 266.0), unit(0.0, 1.0);
  const std::vector<VoxelModel>& models = builtinModels();
  std::vector<PlacementRequest> requests;
  for (std::size_t k = 0; k < count; ++k) {
    requests.push_back({&models[k % models.size()], along(rng), along(rng), 360.0 * unit(rng), 0.5 + 1.5 * unit(rng)});
  }
  return requests;
}

TerrainGrid roughGrid() {
  TerrainGrid grid = flatGrid(128);
  std::mt19937 rng(3);
  for (std::uint16_t& h : grid.heightQ) h = static_cast<std::uint16_t>(2000 + rng() % 200);
  return grid;
}

void expectSameGrid(const TerrainGrid& a, const TerrainGrid& b) {
  EXPECT_EQ(a.heightQ, b.heightQ);
  EXPECT_EQ(a.stickId, b.stickId);
  EXPECT_EQ(a.colourRgba, b.colourRgba);
  ASSERT_EQ(a.sticks->size(), b.sticks->size());
  for (std::uint32_t id = 1; id <= a.sticks->size(); ++id) {
    EXPECT_EQ(a.sticks->entry(id).texels, b.sticks->entry(id).texels) << "table entry " << id;
  }
}

TEST(ObjectPlacement, ABatchOnSeveralThreadsPlacesWhatOneByOneDoes) {
  const std::vector<PlacementRequest> requests = crowdedRequests(2 * ObjectPlacer::kBatchRequests + 1000);  // 3 batches
  TerrainGrid oneByOne = roughGrid(), batched = roughGrid();
  ObjectPlacer single(oneByOne);
  for (const PlacementRequest& r : requests) single.place(*r.model, r.xM, r.yM, r.headingDeg, r.scale);
  const PlacementReport expected = single.finish();
  ObjectPlacer batch(batched);
  batch.place(requests, 3);
  const PlacementReport report = batch.finish();
  EXPECT_EQ(report.placed, expected.placed);
  EXPECT_EQ(report.offGrid, expected.offGrid);
  EXPECT_GT(report.tableEntries, 20u) << "complex sticks placed at many lengths";
  expectSameGrid(oneByOne, batched);
}

TEST(ObjectPlacement, ABatchStopsAtARequestItRefusesWithTheOnesBeforeItPlaced) {
  // Refused in the second batch: the first batch's objects and the second's before it are placed
  const std::size_t refused = ObjectPlacer::kBatchRequests + 500;
  std::vector<PlacementRequest> requests = crowdedRequests(2 * ObjectPlacer::kBatchRequests);
  requests[refused].scale = 100.0;
  TerrainGrid before = roughGrid(), batched = roughGrid();
  ObjectPlacer single(before);
  for (std::size_t k = 0; k < refused; ++k) {
    const PlacementRequest& r = requests[k];
    single.place(*r.model, r.xM, r.yM, r.headingDeg, r.scale);
  }
  single.finish();
  ObjectPlacer batch(batched);
  EXPECT_THROW(batch.place(requests, 2), std::invalid_argument);
  batch.finish();
  expectSameGrid(before, batched);
  // A request without a model is refused too
  TerrainGrid grid = roughGrid();
  ObjectPlacer placer(grid);
  const PlacementRequest none{};
  EXPECT_THROW(placer.place(std::span(&none, 1), 1), std::invalid_argument);
}

TEST(ObjectPlacement, ObjectsOffTheGridAreCountedNotPlaced) {
  TerrainGrid grid = flatGrid(64);
  const std::vector<ObjectPlacement> objects{{"conifer", 50.0, 50.0, 0.0, 1.0}, {"conifer", -500.0, 50.0, 0.0, 1.0}};
  const PlacementReport report = placeObjects(grid, objects);
  EXPECT_EQ(report.placed, 1u);
  EXPECT_EQ(report.offGrid, 1u);
}

TEST(ObjectPlacement, TheListIsReadAndItsMistakesNamed) {
  ScratchDir dir;
  std::ofstream(dir / "ok.csv") << "# a farm\nmodel,x,y,heading,scale\n\nhouse, 10, 20, 30, 1.5\nbarn,1e2,-4,0,1\n";
  const std::vector<ObjectPlacement> ok = readPlacementList(dir / "ok.csv");
  ASSERT_EQ(ok.size(), 2u);
  EXPECT_EQ(ok[0].model, "house");
  EXPECT_EQ(ok[0].headingDeg, 30.0);
  EXPECT_EQ(ok[0].scale, 1.5);
  EXPECT_EQ(ok[1].xM, 100.0);
  std::ofstream(dir / "short.csv") << "model,x,y\nconifer,1,2\n";
  EXPECT_EQ(readPlacementList(dir / "short.csv")[0].scale, 1.0);

  const auto refused = [&](const std::string& text, const std::string& what) {
    std::ofstream(dir / "bad.csv") << text;
    try {
      readPlacementList(dir / "bad.csv");
      ADD_FAILURE() << "accepted " << text;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  refused("name,x,y\n", "bad.csv:1: the header must be model,x,y[,heading[,scale]]");
  refused("model,x,y\nhouse,1\n", "bad.csv:2: 2 values, the header has 3");
  refused("model,x,y\n\nhouse,1,north\n", "bad.csv:3: y 'north' is not a number");
  refused("model,x,y,heading,scale\nhouse,1,2,0,9\n", "bad.csv:2: scale 9 out of range");
  refused("", "empty placement list");
  TerrainGrid grid = flatGrid(16);
  const ObjectPlacement unknown{"castle", 1.0, 1.0, 0.0, 1.0};
  try {
    placeObjects(grid, std::span(&unknown, 1));
    ADD_FAILURE() << "placed a castle";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown model 'castle' (built in: conifer, broadleaf, hedge, house"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace fieldcast::core
