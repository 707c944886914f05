// The tile prefetch (TileCache::prefetch) against the frames it fetches for: once a prefetch for a
// view has been served, a frame of that view reads no missing tile — at full sharpness, with the
// quality knob raised and lowered, and with the grazing-angle rule (one view, four settings). A
// missing tile is answered by a coarser level (counted in TerrainView::missCount): the frame is
// blurrier than asked, and slower. And the order of the request: what the view draws first.
#include "RenderTestUtil.h"

#include <ig_core/BuiltinTerrain.h>
#include <ig_core/Renderer.h>
#include <ig_core/TerrainBuilder.h>
#include <ig_core/TileCache.h>

#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>

namespace fieldcast::core::test {
namespace {

// A 512² built-in terrain at 2 m in 32² tiles (16 × 16 at level 0, five levels), bare, in a database
// file that the tests' caches page from.
class TilePrefetchTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sDir = new std::filesystem::path(std::filesystem::path(::testing::TempDir()) /
                                     ("fieldcast-prefetch-" + std::to_string(::getpid())));
    std::filesystem::create_directories(*sDir);
    BuiltinTerrainSpec spec;
    spec.sizeVox = 512;
    spec.objects = false;
    BuildOptions options;
    options.tileShift = 5;
    writeTerrainDatabase(generateBuiltinTerrain(spec), dbPath(), options);
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    std::filesystem::remove_all(*sDir, ec);
    delete sDir;
  }
  static std::filesystem::path dbPath() { return *sDir / "prefetch.fctdb"; }

  // A cache over the database whose budget holds every tile, with only levels 3 and 4 pinned:
  // levels 0 to 2 are there only if a prefetch asked for them.
  static std::unique_ptr<TileCache> openCache() {
    TileCacheOptions options;
    options.budgetBytes = std::size_t{400} * 32 * 32 * 8;  // 400 tiles; the database has 341
    options.coarseShare = 0.05;                            // 20 tiles: levels 3 and 4 (5 tiles)
    auto cache = std::make_unique<TileCache>(std::make_unique<DatabaseTileSource>(dbPath()), options);
    EXPECT_EQ(cache->stats().pinnedFromLevel, 3);
    return cache;
  }
  // 150 m over the terrain's south-west quarter, looking north-east 30° down.
  static ViewRequest theView(const TerrainView& view) {
    ViewRequest request;
    request.pose = poseAbove(view, 300.0, 300.0, 150.0, 45.0, -30.0);
    request.display = Intrinsics::fromHorizontalFov(160, 120, radians(60.0));
    return request;
  }

  // Misses of one frame of the view rendered with `settings`, after a prefetch for it at the
  // levels of detail `prefetchFor` has been served.
  static std::uint64_t missesOfAFrame(const RenderSettings& settings, const PrefetchLod& prefetchFor) {
    const std::unique_ptr<TileCache> cache = openCache();
    const ViewRequest request = theView(cache->view());
    const FrameLayout layout = layoutFrame(request.display, settings.marginFraction, request.pose.rollRad);
    cache->prefetch(request.pose, glm::dvec3{0.0}, layout.frame, prefetchFor);
    EXPECT_TRUE(cache->waitIdle(std::chrono::seconds(30)));
    const FrameLease lease = cache->lease();
    Renderer renderer(cache->view(), settings, 2);
    const std::uint64_t before = cache->view().missCount();
    (void)renderer.render(request);
    return cache->view().missCount() - before;
  }

  // The priority a prefetch at `lod` gives tile (level, tx, ty); −1 when it does not ask for it.
  static double priorityOf(const PrefetchLod& lod, int level, int tx, int ty) {
    const std::unique_ptr<TileCache> cache = openCache();
    const ViewRequest request = theView(cache->view());
    cache->prefetch(request.pose, glm::dvec3{0.0}, layoutFrame(request.display, 0.1, 0.0).frame, lod);
    for (const TileCache::TileKey& k : cache->lastRequest()) {
      if (k.level == level && k.tx == tx && k.ty == ty) return k.priority;
    }
    return -1.0;
  }

  static std::filesystem::path* sDir;
};
std::filesystem::path* TilePrefetchTest::sDir = nullptr;

RenderSettings withQuality(double quality, double maxAnisotropy = 0.0) {
  RenderSettings s;
  s.quality = quality;
  s.maxAnisotropy = maxAnisotropy;
  return s;
}

// The first-hit descent reads every level's maximum heights from the camera on.
TEST_F(TilePrefetchTest, AFullSharpnessFrameFindsItsTiles) {
  const RenderSettings sharp = withQuality(1.0);
  EXPECT_EQ(missesOfAFrame(sharp, prefetchLod(sharp)), 0u);
}

// At knob 8 this view draws only the pinned levels: what is left to find is what the descent
// reads.
TEST_F(TilePrefetchTest, ACoarseKnobsFrameFindsItsTiles) {
  const RenderSettings coarse = withQuality(8.0);
  EXPECT_EQ(missesOfAFrame(coarse, prefetchLod(coarse)), 0u);
}

// The grazing-angle rule draws a level up to maxLodStretch times nearer.
TEST_F(TilePrefetchTest, AFrameWithTheGrazingRuleFindsItsTiles) {
  const RenderSettings grazing = withQuality(2.0, 2.0);
  EXPECT_EQ(missesOfAFrame(grazing, prefetchLod(grazing)), 0u);
}

// A knob finer than 1 draws each level farther out: a prefetch for full sharpness leaves those
// tiles out (so the checks above can fail).
TEST_F(TilePrefetchTest, AFineKnobsFrameFindsItsTiles) {
  const RenderSettings fine = withQuality(0.5);
  EXPECT_EQ(missesOfAFrame(fine, prefetchLod(fine)), 0u);
  EXPECT_GT(missesOfAFrame(fine, PrefetchLod{}), 0u);
}

// Level 2's tile under the camera (tile (1, 1): 256–512 m) lies nearer than a full-sharpness frame
// draws level 2 (from about 390 m): only the descent reads it, and it comes after the tiles the
// view draws (priority 1 or more). A raised knob, or the grazing rule, draws level 2 there.
TEST_F(TilePrefetchTest, TheTilesAViewDrawsComeFirst) {
  EXPECT_GE(priorityOf(PrefetchLod{1.0, 1.0}, 2, 1, 1), 1.0);
  const double coarse = priorityOf(PrefetchLod{8.0, 1.0}, 2, 1, 1);
  EXPECT_GE(coarse, 0.0);
  EXPECT_LT(coarse, 1.0);
  const double grazing = priorityOf(PrefetchLod{1.0, 4.0}, 2, 1, 1);
  EXPECT_GE(grazing, 0.0);
  EXPECT_LT(grazing, 1.0);
}

}  // namespace
}  // namespace fieldcast::core::test
