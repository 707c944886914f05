// Tile paging with a loader thread, footprint-driven prefetch and epoch-based reclamation.
#include <ig_core/TileCache.h>

#include "Footprint.h"

#include <fieldcast/Conventions.h>

#include <spdlog/spdlog.h>
#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace fieldcast::core {

struct TileCache::Entry {
  TileBuffers data;
  TerrainTile tile;
  int level = 0, tx = 0, ty = 0;
  std::uint64_t lastWanted = 0;  // loader batch that last wanted it (eviction is least recently wanted)
  double priority = 0.0;         // its priority in that batch (TileKey::priority, lower is sooner)
  bool pinned = false;
};

struct TileCache::Retired {
  std::unique_ptr<Entry> entry;
  std::uint64_t epoch = 0;  // epoch at withdrawal: readers that entered at or before it may hold it
  std::chrono::steady_clock::time_point when;
};

namespace {

constexpr std::size_t kLatencyRing = 4096;

}  // namespace

// ---------------------------------------------------------------------------------------------
// FrameLease

FrameLease& FrameLease::operator=(FrameLease&& other) noexcept {
  if (this != &other) {
    release();
    mSlot = other.mSlot;
    other.mSlot = nullptr;
  }
  return *this;
}

void FrameLease::release() noexcept {
  if (mSlot != nullptr) mSlot->store(0, std::memory_order_release);
  mSlot = nullptr;
}

FrameLease TileCache::lease() const noexcept {
  static std::atomic<unsigned> threadCounter{0};
  thread_local const unsigned start = threadCounter.fetch_add(1, std::memory_order_relaxed);
  const std::uint64_t epoch = mEpoch.load(std::memory_order_acquire);
  for (std::size_t k = 0; k < kLeaseSlots; ++k) {
    std::atomic<std::uint64_t>& slot = mLeases[(start + k) % kLeaseSlots].epoch;
    std::uint64_t expected = 0;
    // Sequentially consistent, like the view's tile loads and stores and reclaim()'s slot loads:
    // in their single total order either reclaim() sees this slot taken, or our tile loads see the
    // withdrawal. Plain seq_cst operations rather than fences, so ThreadSanitizer can check it.
    if (slot.compare_exchange_strong(expected, epoch, std::memory_order_seq_cst)) {
      return FrameLease(&slot);
    }
  }
  return FrameLease{};
}

// ---------------------------------------------------------------------------------------------
// Construction

TileCache::TileCache(std::unique_ptr<TileSource> source, const TileCacheOptions& options)
    : mSource(std::move(source)), mOptions(options) {
  const TerrainGeometry& g = mSource->geometry();
  mView = std::make_unique<TerrainView>(g, mSource->sticks());
  const std::size_t voxels = std::size_t{1} << (2 * g.tileShift);
  // Heights, maxima, colours; and stick ids and their bits where the terrain has sticks (counted
  // for every tile: the budget is a bound)
  mTileBytes = voxels * (2 + 2 + 4) + (mSource->sticks() ? voxels * 4 + voxels / 8 : 0) + sizeof(Entry);
  mResident.resize(static_cast<std::size_t>(g.levels));
  mFailed.resize(static_cast<std::size_t>(g.levels));
  for (int level = 0; level < g.levels; ++level) {
    const auto tiles = static_cast<std::size_t>(g.tilesX(level)) * static_cast<std::size_t>(g.tilesY(level));
    mResident[static_cast<std::size_t>(level)].resize(tiles);
    mFailed[static_cast<std::size_t>(level)].assign(tiles, 0);
  }
  mLatencyMs.reserve(kLatencyRing);

  // Pin coarse levels from the top down while they fit in their share of the budget.
  const auto pinnedBudget = static_cast<std::size_t>(static_cast<double>(mOptions.budgetBytes) * mOptions.coarseShare);
  std::size_t pinnedBytes = 0;
  mPinnedFromLevel = g.levels - 1;
  for (int level = g.levels - 1; level >= 0; --level) {
    const std::size_t bytes = mResident[static_cast<std::size_t>(level)].size() * mTileBytes;
    if (level != g.levels - 1 && pinnedBytes + bytes > pinnedBudget) break;
    pinnedBytes += bytes;
    mPinnedFromLevel = level;
  }
  for (int level = g.levels - 1; level >= mPinnedFromLevel; --level) {
    for (int ty = 0; ty < g.tilesY(level); ++ty) {
      for (int tx = 0; tx < g.tilesX(level); ++tx) {
        if (!loadTile(level, tx, ty, true) && level == g.levels - 1) {
          throw TerrainDatabaseError(mSource->name() + ": the top level tile (" + std::to_string(tx) + ", " +
                                     std::to_string(ty) + ") cannot be read; the terrain is unusable");
        }
      }
    }
  }
  mLoader = std::thread([this] { loaderMain(); });
}

TileCache::~TileCache() {
  {
    const std::lock_guard lock(mRequestMutex);
    mStop = true;
  }
  mWake.notify_all();
  if (mLoader.joinable()) mLoader.join();
  // The cache outlives its readers: everything can go now.
  for (int level = 0; level < mView->levels(); ++level) {
    for (int ty = 0; ty < geometry().tilesY(level); ++ty) {
      for (int tx = 0; tx < geometry().tilesX(level); ++tx) mView->publish(level, tx, ty, nullptr);
    }
  }
}

std::size_t TileCache::slotIndex(int level, int tx, int ty) const noexcept {
  return static_cast<std::size_t>(ty) * static_cast<std::size_t>(geometry().tilesX(level)) +
         static_cast<std::size_t>(tx);
}

// ---------------------------------------------------------------------------------------------
// Loader side

bool TileCache::loadTile(int level, int tx, int ty, bool pinned) {
  auto entry = std::make_unique<Entry>();
  const auto start = std::chrono::steady_clock::now();
  try {
    mSource->readTile(level, tx, ty, entry->data);
  } catch (const std::exception& e) {
    mFailed[static_cast<std::size_t>(level)][slotIndex(level, tx, ty)] = 1;
    mLoadFailures.fetch_add(1, std::memory_order_relaxed);
    spdlog::warn("{} — treated as missing, the coarser level is used", e.what());
    return false;
  }
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  {
    const std::lock_guard lock(mLatencyMutex);
    if (mLatencyMs.size() < kLatencyRing) {
      mLatencyMs.push_back(static_cast<float>(ms));
    } else {
      mLatencyMs[mLatencyNext] = static_cast<float>(ms);
    }
    mLatencyNext = (mLatencyNext + 1) % kLatencyRing;
  }
  entry->level = level;
  entry->tx = tx;
  entry->ty = ty;
  entry->pinned = pinned;
  entry->data.stickBits = stickBitsOf(entry->data.stickId);
  entry->tile = TerrainTile{entry->data.heightQ.data(), entry->data.maxHeightQ.data(), entry->data.colourRgba.data(),
                            entry->data.stickId.empty() ? nullptr : entry->data.stickId.data(),
                            entry->data.stickId.empty() ? nullptr : entry->data.stickBits.data()};
  mView->publish(level, tx, ty, &entry->tile);
  mResident[static_cast<std::size_t>(level)][slotIndex(level, tx, ty)] = std::move(entry);
  mResidentBytesLoader += mTileBytes;
  mResidentBytes.store(mResidentBytesLoader, std::memory_order_relaxed);
  mResidentTiles.fetch_add(1, std::memory_order_relaxed);
  mLoads.fetch_add(1, std::memory_order_relaxed);
  if (pinned) mPinnedTiles.fetch_add(1, std::memory_order_relaxed);
  return true;
}

void TileCache::evict(std::size_t level, std::size_t index) {
  std::unique_ptr<Entry> entry = std::move(mResident[level][index]);
  // A seq_cst store (TerrainView::publish): a reader whose lease reclaim() does not see cannot see the tile.
  mView->publish(entry->level, entry->tx, entry->ty, nullptr);
  auto retired = std::make_unique<Retired>();
  retired->epoch = mEpoch.fetch_add(1, std::memory_order_seq_cst);
  retired->when = std::chrono::steady_clock::now();
  retired->entry = std::move(entry);
  mRetired.push_back(std::move(retired));
  mResidentBytesLoader -= mTileBytes;
  mResidentBytes.store(mResidentBytesLoader, std::memory_order_relaxed);
  mResidentTiles.fetch_sub(1, std::memory_order_relaxed);
  mEvictions.fetch_add(1, std::memory_order_relaxed);
  mRetiredCount.store(mRetired.size(), std::memory_order_relaxed);
}

void TileCache::reclaim(bool force) {
  if (mRetired.empty()) return;
  std::uint64_t oldestReader = std::numeric_limits<std::uint64_t>::max();
  for (const LeaseSlot& slot : mLeases) {
    const std::uint64_t e = slot.epoch.load(std::memory_order_seq_cst);
    if (e != 0) oldestReader = std::min(oldestReader, e);
  }
  const auto now = std::chrono::steady_clock::now();
  std::erase_if(mRetired, [&](const std::unique_ptr<Retired>& r) {
    return force || (oldestReader > r->epoch && now - r->when >= mOptions.retireGrace);
  });
  mRetiredCount.store(mRetired.size(), std::memory_order_relaxed);
}

bool TileCache::makeRoom(std::size_t bytes, std::uint64_t batch, double priority) {
  // The budget bounds the live tiles. Evicted tiles still held for readers are freed within a
  // grace period (reclaim()); they overshoot the budget only that briefly.
  while (mResidentBytesLoader + bytes > mOptions.budgetBytes) {
    // The least recently wanted non-pinned tile that the current batch does not want (of those,
    // the one wanted least then); else the one it wants least, if that is clearly less than the
    // tile to load (so the budget ends up holding the batch's first tiles, whatever order earlier
    // batches loaded them in).
    const Entry* best = nullptr;
    std::size_t bestLevel = 0, bestIndex = 0;
    const auto evictsBefore = [batch](const Entry& a, const Entry& b) {
      const bool aWanted = a.lastWanted == batch, bWanted = b.lastWanted == batch;
      if (aWanted != bWanted) return !aWanted;
      if (aWanted || a.lastWanted == b.lastWanted) return a.priority > b.priority;
      return a.lastWanted < b.lastWanted;
    };
    for (std::size_t level = 0; level < mResident.size(); ++level) {
      const auto& tiles = mResident[level];
      for (std::size_t k = 0; k < tiles.size(); ++k) {
        const Entry* e = tiles[k].get();
        if (e != nullptr && !e->pinned && (best == nullptr || evictsBefore(*e, *best))) {
          best = e;
          bestLevel = level;
          bestIndex = k;
        }
      }
    }
    // Every tile is wanted at least about as much: the budget is full, load nothing more. (Not
    // for a hair's difference: priorities move a little every frame, and tiles at the edge of
    // the budget would swap places, a load each.)
    constexpr double kHysteresis = 0.1;
    if (best == nullptr || (best->lastWanted == batch && !(best->priority > priority + kHysteresis))) return false;
    evict(bestLevel, bestIndex);
  }
  return true;
}

void TileCache::loaderMain() {
  std::vector<TileKey> work;
  std::uint64_t batch = 0;  // stamps the tiles each batch wants; older stamps may be evicted
  std::unique_lock lock(mRequestMutex);
  while (!mStop) {
    if (mPending.empty()) {
      mBusy = false;
      mIdle.notify_all();
      mWake.wait_for(lock, std::chrono::milliseconds(100));
      lock.unlock();
      reclaim(false);
      lock.lock();
      continue;
    }
    work.clear();
    work.swap(mPending);
    const std::uint64_t generation = mGeneration;
    ++batch;
    mBusy = true;
    lock.unlock();

    std::stable_sort(work.begin(), work.end(),
                     [](const TileKey& a, const TileKey& b) { return a.priority < b.priority; });
    for (const TileKey& k : work) {
      Entry* e = mResident[static_cast<std::size_t>(k.level)][slotIndex(k.level, k.tx, k.ty)].get();
      if (e != nullptr && e->lastWanted != batch) {  // sorted: a tile asked for twice keeps its first priority
        e->lastWanted = batch;
        e->priority = k.priority;
      }
    }
    for (const TileKey& k : work) {
      {
        const std::lock_guard peek(mRequestMutex);
        if (mStop || mGeneration != generation) break;  // a newer prefetch replaces this one
      }
      const std::size_t index = slotIndex(k.level, k.tx, k.ty);
      if (mResident[static_cast<std::size_t>(k.level)][index] != nullptr) continue;
      if (mFailed[static_cast<std::size_t>(k.level)][index] != 0) continue;
      // Sorted by priority: once no room is left for one tile, none is left for the rest
      if (!makeRoom(mTileBytes, batch, k.priority)) break;
      if (loadTile(k.level, k.tx, k.ty, false)) {
        Entry& e = *mResident[static_cast<std::size_t>(k.level)][index];
        e.lastWanted = batch;
        e.priority = k.priority;
      }
    }
    reclaim(false);
    lock.lock();
  }
  mBusy = false;
  mIdle.notify_all();
}

// ---------------------------------------------------------------------------------------------
// Requests

void TileCache::computeRequest(const Pose& pose, const glm::dvec3& velocityMps, const Intrinsics& camera,
                               const PrefetchLod& lod) {
  const TerrainGeometry& g = geometry();
  mScratch.clear();
  if (mPinnedFromLevel == 0 || camera.widthPx <= 0 || camera.heightPx <= 0) return;
  const double pixelAngle = camera.horizontalFovRad() / camera.widthPx;
  const glm::dvec2 now{pose.positionM.x, pose.positionM.y};
  const glm::dvec2 ahead = now + glm::dvec2(velocityMps.x, velocityMps.y) * mOptions.lookaheadS;
  // A plane a little below the ground under the camera stands in for the terrain in view.
  const double groundM = mView->heightAtM(now.x, now.y, mPinnedFromLevel) - 50.0;
  const double aboveM = std::max(pose.positionM.z - groundM, 1.0);
  const double range = mOptions.maxRangeM;

  // Footprint: rays over the image (widened by 15% for margins and roll) meet the plane.
  std::vector<glm::dvec2>& points = mHullScratch;
  points.clear();
  points.push_back(now);
  points.push_back(ahead);
  const int n = std::max(mOptions.footprintRays, 2);
  for (int b = 0; b < n; ++b) {
    for (int a = 0; a < n; ++a) {
      const double u = (-0.075 + 1.15 * a / (n - 1)) * camera.widthPx;
      const double v = (-0.075 + 1.15 * b / (n - 1)) * camera.heightPx;
      const glm::dvec3 dir = pixelRay(pose, camera, {u, v});
      const double horizontal = std::hypot(dir.x, dir.y);
      if (horizontal < 1e-9) continue;
      double reach = range;
      if (dir.z < -1e-9) reach = std::min(range, aboveM / -dir.z * horizontal);
      const glm::dvec2 offset = glm::dvec2(dir.x, dir.y) / horizontal * reach;
      points.push_back(now + offset);
      points.push_back(ahead + offset);
    }
  }
  std::vector<glm::dvec2>& hull = mFootprintScratch;
  convexHull(points, hull);

  // At knob q level L is drawn out to where its voxels project to q pixels, r(L)/q (r(L): where a
  // level-L voxel spans a pixel): fetched out to r(L) at least, as a knob raised under load comes
  // back to 1. And from the camera on: the first-hit descent reads every level's maximum heights
  // from the camera out to where the level is drawn, and a raised knob or the grazing-angle rule
  // draws coarse levels near the camera (fetched only from about r(L−1), an HD frame's knob raised
  // under load read coarser levels than it asked for there: ten million answers a second, for
  // seconds). A tile nearer than where the level is drawn, from r(L−1)/q (the grazing rule's
  // stretch times nearer), comes after the drawn ones: a coarser level answers the descent too.
  const double quality = std::clamp(lod.quality, 1e-3, 64.0);
  const double reachScale = 1.0 / std::min(quality, 1.0);
  const double nearScale = 1.0 / (std::max(quality, 1.0) * std::max(lod.grazingStretch, 1.0));
  for (int level = 0; level < mPinnedFromLevel; ++level) {
    const double scale = static_cast<double>(1 << level);
    const double rHi = g.spacingM * scale / pixelAngle;
    const double hi = std::min(rHi * (1.0 + mOptions.lodMargin) * reachScale, range);
    const double drawnFrom = level == 0 ? 0.0 : 0.5 * rHi * (1.0 - mOptions.lodMargin) * nearScale;
    const double tileM = g.tileSizeVox() * scale * g.spacingM;
    const double x0 = g.originM.x - 0.5 * g.spacingM;  // west edge of level-0 voxel 0
    const double y0 = g.originM.y - 0.5 * g.spacingM;
    const double reachXY = std::sqrt(std::max(hi * hi - aboveM * aboveM, 0.0));
    if (reachXY <= 0.0) continue;  // too high above the ground for this level
    const glm::dvec2 bmin = glm::min(now, ahead) - reachXY;
    const glm::dvec2 bmax = glm::max(now, ahead) + reachXY;
    const int tx0 = std::max(0, static_cast<int>(std::floor((bmin.x - x0) / tileM)));
    const int ty0 = std::max(0, static_cast<int>(std::floor((bmin.y - y0) / tileM)));
    const int tx1 = std::min(g.tilesX(level) - 1, static_cast<int>(std::floor((bmax.x - x0) / tileM)));
    const int ty1 = std::min(g.tilesY(level) - 1, static_cast<int>(std::floor((bmax.y - y0) / tileM)));
    for (int ty = ty0; ty <= ty1; ++ty) {
      for (int tx = tx0; tx <= tx1; ++tx) {
        const glm::dvec2 rlo{x0 + tx * tileM, y0 + ty * tileM};
        const glm::dvec2 rhi = rlo + tileM;
        const auto within = [&](const glm::dvec2& p, double& nearest) {
          const double dn = distanceToRect(p, rlo, rhi);
          nearest = std::sqrt(dn * dn + aboveM * aboveM);
          return nearest <= hi;
        };
        double dNow = 0.0, dAhead = 0.0;
        const bool wantedNow = within(now, dNow);
        const bool wantedAhead = within(ahead, dAhead);
        if (!wantedNow && !wantedAhead) continue;
        if (!polygonTouchesRect(hull, rlo, rhi)) continue;
        const double df = farthestInRect(now, rlo, rhi);
        const bool drawnNow = wantedNow && std::sqrt(df * df + aboveM * aboveM) >= drawnFrom;
        // Nearest first within the band drawn now or at quality 1; then what only the first-hit
        // descent reads, and the view ahead.
        const double priority = drawnNow ? dNow / hi : 1.0 + (wantedNow ? dNow : dAhead) / hi;
        mScratch.push_back({level, tx, ty, priority});
      }
    }
  }
}

void TileCache::prefetch(const Pose& pose, const glm::dvec3& velocityMps, const Intrinsics& camera,
                         const PrefetchLod& lod) {
  computeRequest(pose, velocityMps, camera, lod);
  std::uint64_t hits = 0;
  for (const TileKey& k : mScratch) {
    if (mView->tile(k.level, k.tx, k.ty) != nullptr) ++hits;
  }
  mPrefetchCalls.fetch_add(1, std::memory_order_relaxed);
  mRequested.fetch_add(mScratch.size(), std::memory_order_relaxed);
  mRequestedResident.fetch_add(hits, std::memory_order_relaxed);
  {
    const std::lock_guard lock(mRequestMutex);
    mLast.assign(mScratch.begin(), mScratch.end());
    mPending.swap(mScratch);
    ++mGeneration;
  }
  mWake.notify_one();
}

void TileCache::prefetch(const Pose& pose, const glm::dvec3& velocityMps, double hfovRad) {
  prefetch(pose, velocityMps, Intrinsics::fromHorizontalFov(1024, 768, hfovRad));
}

void TileCache::request(int level, int tx, int ty, double priority) {
  if (level < 0 || level >= mView->levels() || tx < 0 || ty < 0 || tx >= geometry().tilesX(level) ||
      ty >= geometry().tilesY(level)) {
    return;
  }
  {
    const std::lock_guard lock(mRequestMutex);
    mPending.push_back({level, tx, ty, priority});
  }
  mWake.notify_one();
}

bool TileCache::waitIdle(std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mRequestMutex);
  return mIdle.wait_for(lock, timeout, [this] { return mPending.empty() && !mBusy; });
}

std::vector<TileCache::TileKey> TileCache::lastRequest() const {
  const std::lock_guard lock(mRequestMutex);
  return mLast;
}

TileCacheStats TileCache::stats() const {
  TileCacheStats s;
  s.residentTiles = mResidentTiles.load(std::memory_order_relaxed);
  s.residentBytes = mResidentBytes.load(std::memory_order_relaxed);
  s.budgetBytes = mOptions.budgetBytes;
  s.pinnedTiles = mPinnedTiles.load(std::memory_order_relaxed);
  s.pinnedFromLevel = mPinnedFromLevel;
  s.loads = mLoads.load(std::memory_order_relaxed);
  s.loadFailures = mLoadFailures.load(std::memory_order_relaxed);
  s.evictions = mEvictions.load(std::memory_order_relaxed);
  s.retiredPending = mRetiredCount.load(std::memory_order_relaxed);
  s.prefetchCalls = mPrefetchCalls.load(std::memory_order_relaxed);
  s.requestedTiles = mRequested.load(std::memory_order_relaxed);
  s.requestedResident = mRequestedResident.load(std::memory_order_relaxed);
  s.prefetchHitRate =
      s.requestedTiles == 0 ? 1.0 : static_cast<double>(s.requestedResident) / static_cast<double>(s.requestedTiles);
  s.viewMisses = mView->missCount();
  std::vector<float> latencies;
  {
    const std::lock_guard lock(mLatencyMutex);
    latencies = mLatencyMs;
  }
  if (!latencies.empty()) {
    std::sort(latencies.begin(), latencies.end());
    const auto at = [&](double q) {
      return static_cast<double>(latencies[static_cast<std::size_t>(q * static_cast<double>(latencies.size() - 1))]);
    };
    s.loadP50Ms = at(0.5);
    s.loadP99Ms = at(0.99);
    s.loadMaxMs = latencies.back();
  }
  return s;
}

}  // namespace fieldcast::core
