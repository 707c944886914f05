#include "HostDatabases.h"

#include <spdlog/spdlog.h>

#include <chrono>

namespace fieldcast::app {

HostDatabases::HostDatabases(OpenDatabase current, std::vector<HostDatabase> others, core::GeodeticOrigin origin,
                             TerrainInUse terrainInUse, SwitchRenderer switchRenderer)
    : mOthers(std::move(others)),
      mOrigin(origin),
      mTerrainInUse(std::move(terrainInUse)),
      mSwitchRenderer(std::move(switchRenderer)),
      mCurrent(std::move(current)) {
  mLoader = std::thread([this] { loaderMain(); });
}

HostDatabases::~HostDatabases() {
  {
    const std::lock_guard lock(mMutex);
    mStop = true;
  }
  mWake.notify_all();
  mLoader.join();
}

const HostDatabase* HostDatabases::find(std::int8_t number) const {
  for (const HostDatabase& d : mOthers) {
    if (d.number == number) return &d;
  }
  return nullptr;
}

void HostDatabases::request(std::int8_t number) {
  std::unique_lock lock(mMutex);
  if (number <= 0 || number == mLoading || number == mWanted) return;
  if (number == mCurrent.number) {
    mRefused = false;
    mWanted = 0;  // the host changed its mind before a load started: stay
    return;
  }
  if (find(number) == nullptr) {
    if (!mRefused) spdlog::warn("host: database {} requested; this IG has no database of that number", number);
    mRefused = true;
    return;
  }
  mRefused = false;
  mWanted = number;
  lock.unlock();
  mWake.notify_all();
}

std::optional<OpenDatabase> HostDatabases::switchIfLoaded() {
  std::unique_lock lock(mMutex);
  if (!mLoaded) return std::nullopt;
  OpenDatabase next = std::move(*mLoaded);
  mLoaded.reset();
  mLoading = 0;
  mRetiring = std::move(mCurrent.terrain);  // closed by the loader once the renderer has let go
  mCurrent = next;
  ++mSwitches;
  lock.unlock();
  mSwitchRenderer(*next.terrain);
  mWake.notify_all();
  spdlog::info("host: database {} loaded: {}", next.number, next.terrain->sourceName());
  return next;
}

std::int8_t HostDatabases::startOfFrameNumber() const {
  const std::lock_guard lock(mMutex);
  if (mRefused) return kNotAvailable;
  const std::int8_t loading = mLoading != 0 ? mLoading : mWanted;
  return loading != 0 ? static_cast<std::int8_t>(-loading) : mCurrent.number;
}

OpenDatabase HostDatabases::current() const {
  const std::lock_guard lock(mMutex);
  return mCurrent;
}

std::uint64_t HostDatabases::switches() const {
  const std::lock_guard lock(mMutex);
  return mSwitches;
}

std::uint64_t HostDatabases::failures() const {
  const std::lock_guard lock(mMutex);
  return mFailures;
}

void HostDatabases::loaderMain() {
  std::unique_lock lock(mMutex);
  while (!mStop) {
    // The renderer tells nothing back: while a database waits to be closed, look again every
    // 50 ms (a wake-up, not a predicate — the retiring database alone must not make this spin).
    const auto workToStart = [this] { return mStop || (mWanted != 0 && !mLoaded && !mRetiring); };
    if (mRetiring) {
      mWake.wait_for(lock, std::chrono::milliseconds(50), workToStart);
    } else {
      mWake.wait(lock, [&] { return workToStart() || mRetiring != nullptr; });
    }
    if (mStop) break;
    if (mRetiring && mTerrainInUse() == mCurrent.terrain.get()) {
      std::shared_ptr<core::TileCache> closing = std::move(mRetiring);
      lock.unlock();
      const std::string name = closing->sourceName();
      closing.reset();  // closes the file and frees its tiles, off the link and render threads
      spdlog::info("host: closed the database left behind ({})", name);
      lock.lock();
      continue;
    }
    // One load at a time, and not before the last switch has settled (two old databases at most).
    if (mWanted == 0 || mLoaded || mRetiring) continue;
    const std::int8_t number = mWanted;
    mWanted = 0;
    mLoading = number;
    const HostDatabase* database = find(number);
    lock.unlock();
    std::optional<OpenDatabase> opened;
    try {
      const auto started = std::chrono::steady_clock::now();
      spdlog::info("host: loading database {} while database {} renders", number, current().number);
      OpenDatabase d;
      d.number = number;
      d.terrain = core::openTerrain(database->terrain);
      d.georeference =
          std::make_shared<const core::Georeference>(core::Georeference::forTerrain(d.terrain->crs(), mOrigin));
      spdlog::info("host: database {} open in {:.2f} s ({}, {})", number,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
                   d.terrain->sourceName(), d.georeference->description());
      opened = std::move(d);
    } catch (const std::exception& e) {
      spdlog::error("host: database {} could not be loaded: {}", number, e.what());
    }
    lock.lock();
    if (opened) {
      mLoaded = std::move(opened);
    } else {
      ++mFailures;
      mLoading = 0;
      mRefused = true;  // Start of Frame says "not available" until the host asks again
    }
  }
}

}  // namespace fieldcast::app
