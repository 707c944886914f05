#pragma once
// Paging (DESIGN.md §2): a tile cache over a terrain database that publishes tiles into a
// TerrainView. A loader thread reads tiles by priority; prefetch() turns the camera's pose,
// velocity and field of view into the tiles the next frames need (the view footprint, extended in
// the direction of motion, each level out to where its voxels project to about a pixel). The coarse
// levels stay resident, so a renderer asking for a missing tile gets the best resident coarser
// level (the miss is counted in TerrainView::missCount) and never waits for I/O.
//
// Reclamation rule for readers of tile pointers (renderers, height queries):
//   Hold a FrameLease (TileCache::lease(), RT-safe, lock-free) while using pointers or samples
//   from the view, typically one per frame per render thread. An evicted tile is freed only once
//   every lease taken before its withdrawal has ended AND a grace period (default 1 s) has passed.
//   A reader without a lease is safe as long as it holds no tile pointer longer than the grace period.

#include <ig_core/PrefetchLod.h>
#include <ig_core/TerrainDatabase.h>
#include <ig_core/TerrainView.h>

#include <fieldcast/Intrinsics.h>
#include <fieldcast/Pose.h>

#include <glm/vec3.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace fieldcast::core {

/// Where a cache's tiles come from. The database is the real one; tests wrap it (e.g. to be slow).
class TileSource {
 public:
  virtual ~TileSource() = default;
  /// Geometry of the terrain (levels and tile shift included).
  virtual const TerrainGeometry& geometry() const = 0;
  /// Reads and decodes one tile into `out`. Throws TerrainDatabaseError. Called from one thread at a time.
  virtual void readTile(int level, int tx, int ty, TileBuffers& out) = 0;
  /// Names the source in logs and errors (the file path).
  virtual std::string name() const = 0;
  /// CRS of world x, y (DatabaseLayout::crs); empty when the terrain has none.
  virtual std::string crs() const { return {}; }
  /// The stick table the tiles' stick ids point into; null when the terrain has none.
  virtual std::shared_ptr<const StickTable> sticks() const { return nullptr; }
};

/// A TileSource reading a database file.
class DatabaseTileSource final : public TileSource {
 public:
  /// Opens and validates `path`. Throws TerrainDatabaseError.
  explicit DatabaseTileSource(const std::filesystem::path& path) : mReader(path) {}
  const TerrainGeometry& geometry() const override { return mReader.geometry(); }
  void readTile(int level, int tx, int ty, TileBuffers& out) override { mReader.readTile(level, tx, ty, out); }
  std::string name() const override { return mReader.path().string(); }
  std::string crs() const override { return mReader.layout().crs; }
  std::shared_ptr<const StickTable> sticks() const override { return mReader.sticks(); }
  const DatabaseReader& reader() const noexcept { return mReader; }

 private:
  DatabaseReader mReader;
};

/// Tuning of a tile cache.
struct TileCacheOptions {
  std::size_t budgetBytes = std::size_t{1} << 30;  ///< tile memory; the coarse levels count against it
  double coarseShare = 0.25;   ///< at most this share of the budget is pinned to coarse levels (top level always)
  double lookaheadS = 2.0;     ///< prefetch where the camera will be this many seconds ahead
  double maxRangeM = 40000.0;  ///< farthest distance the view can need terrain
  /// Each level is fetched this fraction farther than it is drawn and counted as drawn from this
  /// fraction nearer: the renderer switches levels on depth along the view axis, the prefetch
  /// measures distance from the camera
  double lodMargin = 0.3;
  int footprintRays = 9;                        ///< rays per image side sampled to find the view footprint
  std::chrono::milliseconds retireGrace{1000};  ///< see the reclamation rule above
};

/// Counters and figures of a cache (a snapshot).
struct TileCacheStats {
  std::uint64_t residentTiles = 0;
  std::uint64_t residentBytes = 0;  ///< live tiles (≤ budget); retired tiles awaiting readers not included
  std::uint64_t budgetBytes = 0;
  std::uint64_t pinnedTiles = 0;   ///< coarse-level tiles that never leave
  int pinnedFromLevel = 0;         ///< levels ≥ this are pinned
  std::uint64_t loads = 0;         ///< tiles read from the source
  std::uint64_t loadFailures = 0;  ///< corrupt or unreadable tiles (each logged once, never retried)
  std::uint64_t evictions = 0;
  std::uint64_t retiredPending = 0;  ///< evicted tiles waiting for readers to move on
  std::uint64_t prefetchCalls = 0;
  std::uint64_t requestedTiles = 0;     ///< tiles prefetch() asked for, summed over calls
  std::uint64_t requestedResident = 0;  ///< of those, already resident when asked
  double prefetchHitRate = 0.0;         ///< requestedResident / requestedTiles
  std::uint64_t viewMisses = 0;         ///< samples answered by a coarser level (TerrainView::missCount)
  double loadP50Ms = 0.0;               ///< tile read + decode latency over the last 4096 loads
  double loadP99Ms = 0.0;
  double loadMaxMs = 0.0;
};

class TileCache;

/// Marks a reader as active: tiles withdrawn while it lives are not freed. RT-safe, lock-free,
/// cheap (one atomic exchange). Movable, not copyable.
class FrameLease {
 public:
  FrameLease() = default;
  FrameLease(FrameLease&& other) noexcept : mSlot(other.mSlot) { other.mSlot = nullptr; }
  FrameLease& operator=(FrameLease&& other) noexcept;
  FrameLease(const FrameLease&) = delete;
  FrameLease& operator=(const FrameLease&) = delete;
  ~FrameLease() { release(); }
  /// Ends the lease early.
  void release() noexcept;
  /// False when every lease slot was taken (the grace period still protects the reader).
  bool active() const noexcept { return mSlot != nullptr; }

 private:
  friend class TileCache;
  explicit FrameLease(std::atomic<std::uint64_t>* slot) noexcept : mSlot(slot) {}
  std::atomic<std::uint64_t>* mSlot = nullptr;
};

/// A paged terrain: a TerrainView kept filled from a TileSource by a loader thread.
class TileCache {
 public:
  /// Takes the source, loads and pins the coarse levels (blocking, at start-up only) and starts the
  /// loader. Throws TerrainDatabaseError if the top level cannot be read.
  TileCache(std::unique_ptr<TileSource> source, const TileCacheOptions& options);
  ~TileCache();
  TileCache(const TileCache&) = delete;
  TileCache& operator=(const TileCache&) = delete;

  /// The renderer's view. Lock-free, never blocks; see the reclamation rule above.
  const TerrainView& view() const noexcept { return *mView; }
  const TerrainGeometry& geometry() const noexcept { return mView->geometry(); }
  /// Where the tiles come from (a file path).
  std::string sourceName() const { return mSource->name(); }
  /// CRS of world x, y, empty when none: Georeference::forTerrain(crs()) places latitude/longitude.
  std::string crs() const { return mSource->crs(); }

  /// Takes a lease for the current frame. RT-safe, lock-free.
  FrameLease lease() const noexcept;

  /// Terrain height at world (x, y), bilinear at `level`, from the best resident level. RT-safe.
  double heightAtM(double xM, double yM, int level = 0) const noexcept { return mView->heightAtM(xM, yM, level); }

  /// Asks for the tiles a camera at `pose` moving at `velocityMps` (world m/s) with intrinsics
  /// `camera` will need, for frames drawn at the levels of detail `lod`; replaces the previous
  /// request. Call once per frame from one thread. Never blocks on I/O (takes a mutex the loader
  /// holds only to swap request lists).
  void prefetch(const Pose& pose, const glm::dvec3& velocityMps, const Intrinsics& camera, const PrefetchLod& lod = {});
  /// Same, for a horizontal field of view in radians (4:3 image, 1024 pixels wide).
  void prefetch(const Pose& pose, const glm::dvec3& velocityMps, double hfovRad);

  /// Asks for one tile explicitly (lower priority value = sooner), after the current request.
  /// The next prefetch() replaces requests not yet served. The priority is weighed against
  /// prefetch()'s, for the order of loads and for eviction: below 1 the tiles the view draws
  /// (nearest first), 1 to 2 those only its first-hit descent reads and those only ahead; a
  /// negative priority comes before all of them.
  void request(int level, int tx, int ty, double priority = 0.0);

  /// Waits until the loader has nothing left to load (or `timeout`); true when idle. For tools and tests.
  bool waitIdle(std::chrono::milliseconds timeout) const;

  /// A snapshot of the counters. Thread-safe.
  TileCacheStats stats() const;

  /// Tiles prefetch() last asked for (level, tx, ty), for tools and tests.
  struct TileKey {
    int level, tx, ty;
    double priority;
  };
  std::vector<TileKey> lastRequest() const;

 private:
  struct Entry;
  struct Retired;
  static constexpr std::size_t kLeaseSlots = 64;
  struct alignas(64) LeaseSlot {
    std::atomic<std::uint64_t> epoch{0};  // 0: free; else the epoch at which the reader entered
  };

  void loaderMain();
  bool loadTile(int level, int tx, int ty, bool pinned);
  bool makeRoom(std::size_t bytes, std::uint64_t batch, double priority);
  void evict(std::size_t level, std::size_t index);
  void reclaim(bool force);
  std::size_t slotIndex(int level, int tx, int ty) const noexcept;
  void computeRequest(const Pose& pose, const glm::dvec3& velocityMps, const Intrinsics& camera,
                      const PrefetchLod& lod);

  std::unique_ptr<TileSource> mSource;
  std::unique_ptr<TerrainView> mView;
  TileCacheOptions mOptions;
  std::size_t mTileBytes = 0;
  int mPinnedFromLevel = 0;

  // Owned by the loader thread (and the constructor/destructor).
  std::vector<std::vector<std::unique_ptr<Entry>>> mResident;  // per level, per tile
  std::vector<std::vector<std::uint8_t>> mFailed;              // per level, per tile: corrupt, never retried
  std::vector<std::unique_ptr<Retired>> mRetired;
  std::uint64_t mResidentBytesLoader = 0;

  // Reclamation.
  mutable std::array<LeaseSlot, kLeaseSlots> mLeases{};
  std::atomic<std::uint64_t> mEpoch{1};

  // Requests: prefetch() fills mScratch, then swaps it into mPending under mRequestMutex.
  mutable std::mutex mRequestMutex;
  mutable std::condition_variable mWake;
  mutable std::condition_variable mIdle;
  std::vector<TileKey> mPending;
  std::vector<TileKey> mLast;
  std::uint64_t mGeneration = 0;
  bool mStop = false;
  bool mBusy = false;
  std::vector<TileKey> mScratch;              // prefetch thread only
  std::vector<glm::dvec2> mHullScratch;       // prefetch thread only: footprint points
  std::vector<glm::dvec2> mFootprintScratch;  // prefetch thread only: their convex hull

  // Counters.
  std::atomic<std::uint64_t> mResidentTiles{0};
  std::atomic<std::uint64_t> mResidentBytes{0};
  std::atomic<std::uint64_t> mPinnedTiles{0};
  std::atomic<std::uint64_t> mLoads{0};
  std::atomic<std::uint64_t> mLoadFailures{0};
  std::atomic<std::uint64_t> mEvictions{0};
  std::atomic<std::uint64_t> mRetiredCount{0};
  std::atomic<std::uint64_t> mPrefetchCalls{0};
  std::atomic<std::uint64_t> mRequested{0};
  std::atomic<std::uint64_t> mRequestedResident{0};
  mutable std::mutex mLatencyMutex;
  std::vector<float> mLatencyMs;  // ring of the last 4096
  std::size_t mLatencyNext = 0;

  std::thread mLoader;
};

}  // namespace fieldcast::core
