#pragma once
// The databases a CIGI host may switch between (IG Control's database number, issue 19): the one
// of [terrain], opened at start, and those of [[host.database]]. A request opens the database on
// a loader thread while the current one goes on rendering and answering; once it is open, the
// link thread switches to it between two fields (switchIfLoaded) and the render loop renders from
// it from its next frame. The database left behind is closed on the loader thread once no frame
// in flight reads it any more.
//
// Start of Frame's database number follows the CIGI convention: the loaded database's number;
// its negative while another is loading; −128 when the host asked for a number this IG does not
// have (until it asks for one it has, or for the current one).

#include <service/ServiceConfig.h>

#include <ig_core/Georeference.h>
#include <ig_core/TileCache.h>

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace fieldcast::app {

/// An open database and where it lies on the Earth.
struct OpenDatabase {
  std::int8_t number = 0;
  std::shared_ptr<core::TileCache> terrain;
  std::shared_ptr<const core::Georeference> georeference;
};

class HostDatabases {
 public:
  /// Start of Frame's number after a request for a database this IG does not have.
  static constexpr std::int8_t kNotAvailable = -128;

  /// The terrain in use by the renderer now (Channel::terrainSettled), polled before the database
  /// left behind by a switch is closed. Any thread.
  using TerrainInUse = std::function<const core::TileCache*()>;
  /// Makes the renderer render from `terrain` (Channel::switchTerrain). Called on the link thread.
  using SwitchRenderer = std::function<void(core::TileCache& terrain)>;

  /// `current` is the database open at start (number `currentNumber`); `others` may be loaded on
  /// request, each placed through its CRS or, without one, the tangent plane at `origin`.
  HostDatabases(OpenDatabase current, std::vector<HostDatabase> others, core::GeodeticOrigin origin,
                TerrainInUse terrainInUse, SwitchRenderer switchRenderer);
  ~HostDatabases();
  HostDatabases(const HostDatabases&) = delete;
  HostDatabases& operator=(const HostDatabases&) = delete;

  /// IG Control's database number (link thread): 0 or the current one asks nothing; a number
  /// loading already is left loading; another known number starts loading it (replacing a load
  /// not yet started); an unknown one is refused (kNotAvailable in Start of Frame).
  void request(std::int8_t number);
  /// When a requested database has finished opening (link thread): makes it the current one,
  /// switches the renderer to it and returns it. Nothing otherwise.
  std::optional<OpenDatabase> switchIfLoaded();
  /// What Start of Frame reports now (see the file comment). Any thread.
  std::int8_t startOfFrameNumber() const;
  /// The current database. Any thread.
  OpenDatabase current() const;
  /// Databases opened and switched to so far, and loads that failed (logged). Any thread.
  std::uint64_t switches() const;
  std::uint64_t failures() const;

 private:
  void loaderMain();
  const HostDatabase* find(std::int8_t number) const;

  std::vector<HostDatabase> mOthers;
  core::GeodeticOrigin mOrigin;
  TerrainInUse mTerrainInUse;
  SwitchRenderer mSwitchRenderer;

  mutable std::mutex mMutex;
  std::condition_variable mWake;
  OpenDatabase mCurrent;
  std::int8_t mWanted = 0;   // a load asked for and not started yet (0: none)
  std::int8_t mLoading = 0;  // the load in progress or finished and not switched to (0: none)
  std::optional<OpenDatabase> mLoaded;
  std::shared_ptr<core::TileCache> mRetiring;  // the database left behind, until the renderer lets go
  bool mRefused = false;                       // the last request named no database of ours
  bool mStop = false;
  std::uint64_t mSwitches = 0, mFailures = 0;
  std::thread mLoader;
};

}  // namespace fieldcast::app
