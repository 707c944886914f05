// The tile prefetch (TileCache::prefetch) against the frames it fetches for: once a prefetch for a
// view has been served, a frame of that view reads no missing tile, at any quality knob and with the
// grazing-angle rule. A missing tile is answered by a coarser level (counted in
// TerrainView::missCount): the frame is blurrier than asked, and slower.
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

  // Misses of one frame of the view rendered with `settings`, after a prefetch for it at quality
  // knob `prefetchQuality` has been served. The budget holds every tile; only levels 3
  // and 4 are pinned, so levels 0 to 2 are there only if the prefetch asked for them.
  static std::uint64_t missesOfAFrame(const RenderSettings& settings, double prefetchQuality) {
    TileCacheOptions options;
    options.budgetBytes = std::size_t{400} * 32 * 32 * 8;  // 400 tiles; the database has 341
    options.coarseShare = 0.05;                            // 20 tiles: levels 3 and 4 (5 tiles)
    TileCache cache(std::make_unique<DatabaseTileSource>(dbPath()), options);
    EXPECT_EQ(cache.stats().pinnedFromLevel, 3);
    ViewRequest request;
    request.pose = poseAbove(cache.view(), 300.0, 300.0, 150.0, 45.0, -30.0);
    request.display = Intrinsics::fromHorizontalFov(160, 120, radians(60.0));
    const FrameLayout layout = layoutFrame(request.display, settings.marginFraction, request.pose.rollRad);
    cache.prefetch(request.pose, glm::dvec3{0.0}, layout.frame, prefetchQuality);
    EXPECT_TRUE(cache.waitIdle(std::chrono::seconds(30)));
    const FrameLease lease = cache.lease();
    Renderer renderer(cache.view(), settings, 2);
    const std::uint64_t before = cache.view().missCount();
    (void)renderer.render(request);
    return cache.view().missCount() - before;
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
TEST_F(TilePrefetchTest, AFullSharpnessFrameFindsItsTiles) { EXPECT_EQ(missesOfAFrame(withQuality(1.0), 1.0), 0u); }

// The knob raised under load draws each level nearer the camera than full sharpness does.
TEST_F(TilePrefetchTest, ACoarseKnobsFrameFindsItsTiles) { EXPECT_EQ(missesOfAFrame(withQuality(8.0), 8.0), 0u); }

// The grazing-angle rule draws a level up to maxLodStretch times nearer again.
TEST_F(TilePrefetchTest, AFrameWithTheGrazingRuleFindsItsTiles) {
  EXPECT_EQ(missesOfAFrame(withQuality(2.0, 2.0), 2.0), 0u);
}

// A knob finer than 1 draws each level farther out: a prefetch for full sharpness leaves those
// tiles out (so the checks above can fail).
TEST_F(TilePrefetchTest, AFineKnobsFrameFindsItsTiles) {
  EXPECT_EQ(missesOfAFrame(withQuality(0.5), 0.5), 0u);
  EXPECT_GT(missesOfAFrame(withQuality(0.5), 1.0), 0u);
}

}  // namespace
}  // namespace fieldcast::core::test
