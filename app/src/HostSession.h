#pragma once
// What the host's CIGI packets mean to this IG (io_bridge/src/host/README.md has the packet
// table): IG Control's mode, frame numbers and database number (HostDatabases switches between
// two fields), the ownship's pose and rates (entity 0) into the
// host motion source, other entities into a table, HAT/HOT requests answered from the terrain,
// Line of Sight Segment and Vector requests answered by a level-0 march (core::lineOfSight),
// Atmosphere Control's visibility published as the haze range, Celestial Sphere Control's date and
// time as the sun (CelestialClock.h) over the database's centre; and, once per field, the Start of
// Frame with the answers due. Runs on the HostLink's thread.
//
// Heights are those of the surface the renderer draws at full resolution (bilinear between the
// level-0 voxel centres). When a request's level-0 tiles are not resident, they are requested
// ahead of the prefetch and the answer waits for them (at most 100 ms, then the best resident
// level answers), so an answer may come one or more fields after its request. LOS requests wait
// the same way for the level-0 tiles under their whole segment (or vector, to its maximum range).

#include "CelestialClock.h"
#include "HostDatabases.h"
#include "SceneEntities.h"

#include <fieldcast/Conventions.h>
#include <fieldcast/Intrinsics.h>
#include <fieldcast/SeqLock.h>
#include <fieldcast/Time.h>
#include <ig_core/Georeference.h>
#include <ig_core/TileCache.h>
#include <io_bridge/HostLink.h>
#include <motion/HostMotion.h>
#include <prp_warp/PostProcess.h>

#include <glm/vec2.hpp>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <variant>
#include <vector>

namespace fieldcast::app {

/// Start of Frame's IG status codes (CIGI leaves them to the IG; 0 is normal).
enum class HostIgStatus : std::uint8_t {
  Normal = 0,
  OwnshipHeld = 1,  ///< the host fell silent for longer than the extrapolation bound: the pose is held
};

/// Figures of the session. Read from any thread.
struct HostSessionFigures {
  std::uint64_t ownshipUpdates = 0;
  std::uint64_t hatHotRequests = 0;
  std::uint64_t hatHotAnswered = 0;  ///< valid answers (inside the database)
  std::uint64_t losRequests = 0;
  std::uint64_t losHits = 0;           ///< LOS answers that met the terrain
  std::uint64_t periodicRequests = 0;  ///< HAT/HOT and LOS requests with an update period, active now
  std::uint64_t periodicAnswers = 0;   ///< answers those requests gave after their first
  std::uint64_t periodicRefused = 0;   ///< periodic requests answered once only: the table was full
  std::uint64_t requestsRefused = 0;   ///< HAT/HOT and LOS requests not answered: too many were waiting
  std::uint64_t otherEntities = 0;     ///< entities other than the ownship, active now
  std::uint64_t modeChanges = 0;
  std::uint32_t lastHostFrame = 0;
  std::uint64_t viewControls = 0;            ///< View Controls addressed to this IG's view and applied
  std::uint64_t viewControlsIgnored = 0;     ///< addressed to it but not applicable (another entity, not finite)
  std::uint64_t viewDefinitions = 0;         ///< View Definitions addressed to this IG's view and applied
  std::uint64_t viewDefinitionsIgnored = 0;  ///< addressed to it but not a frustum this IG renders
  std::uint64_t celestialControls = 0;       ///< Celestial Sphere Controls that set or ran the time of day
  std::uint64_t celestialRefused = 0;        ///< with Date/Time Valid set but not a date (13/40/2024)
};

/// The view this IG renders as a host addresses it with View Control, and how to move it.
struct HostView {
  std::uint16_t viewId = 0;
  std::uint8_t groupId = 0;                      ///< the view group it belongs to; 0: none
  ViewOffset offset;                             ///< the configured eye offset ([view]), where View Controls start from
  std::function<void(const ViewOffset&)> apply;  ///< moves the channel's eye (called on the link thread)
  Intrinsics display;                            ///< the configured display window, where View Definitions start from
  std::function<void(const Intrinsics&)> applyDisplay;  ///< changes its frustum (called on the link thread)
  std::function<void(warp::Mirror)> applyMirror;        ///< mirrors its fields (called on the link thread)
};

/// The renderer's haze range (haze covers 1 − exp(−r/R) at range r) for a meteorological
/// visibility: the range where a dark object's contrast against the horizon falls to 5 % (the
/// WMO's meteorological optical range), so R = V / ln 20 and haze covers 95 % at V.
inline double hazeRangeForVisibility(double visibilityM) { return visibilityM / std::log(20.0); }

class HostSession final : public io::HostHandler {
 public:
  /// `ownship` receives entity 0's samples; `terrain` answers height requests; `georeference`
  /// places geodetic positions (used on the link's thread only).
  HostSession(motion::HostMotion& ownship, core::TileCache& terrain,
              std::shared_ptr<const core::Georeference> georeference, std::int8_t databaseNumber, const Clock& clock);

  /// The databases IG Control may switch between (null: none; Start of Frame then reports the
  /// number given at construction). Set before the link starts.
  void setDatabases(HostDatabases* databases) noexcept { mDatabases = databases; }
  /// The view View Control may move (without one, View Controls are ignored). Set before the link starts.
  void setView(HostView view) { mView = std::move(view); }
  /// The time zone the host's Celestial Sphere Control hour and minute are in: hours east of UTC
  /// ([host] celestial_utc_offset_h; 0 until set). Set before the link starts.
  void setUtcOffset(double hours) noexcept { mCelestial = CelestialClock(hours); }

  void onMessage(const io::HostMessage& message) override;
  bool onField(const io::FieldAnnouncement& field, io::cigi::IgMessageBuilder& out) override;

  /// The mode the host last commanded (Operate until told otherwise). Any thread.
  io::cigi::IgMode mode() const noexcept { return mMode.load(std::memory_order_relaxed); }
  HostSessionFigures figures() const noexcept;
  /// The haze range the host's Atmosphere Control asks for (hazeRangeForVisibility of its
  /// visibility range), at least 1 m; 0 until the host sends one. The render loop reads it before
  /// each frame. Any thread.
  const std::atomic<double>& hazeRangeM() const noexcept { return mHazeRangeM; }
  /// The sun of the host's time of day over the database's centre (grid north); empty until the
  /// host sends a date and time. Moves on once a second of the IG's clock while the host's
  /// ephemeris model runs. The render loop reads it before each frame. Any thread.
  const SeqLock<std::optional<core::SunDirection>>& sun() const noexcept { return mSun; }
  /// The host's entities other than the ownship as last sent (an attached one with its parent
  /// and offset: hostEntityPose places it), into `out`. Any thread (the render loop, once a frame).
  void copyEntities(std::vector<HostEntitySample>& out) const;
  /// The scene's drawn entities at an instant (SceneEntities::at): line-of-sight answers meet them
  /// as the pictures show them. Set before the link starts; empty: terrain only.
  using EntityScene = std::function<void(TimePoint, std::vector<core::EntityInstance>&)>;
  void setEntityScene(EntityScene scene) { mEntityScene = std::move(scene); }

 private:
  double unwrapHostTime(std::uint32_t ticks);
  // Answers from `database` from now on (a database switch, between two fields).
  void switchTo(OpenDatabase database);
  bool addressesThisView(std::uint16_t viewId, std::uint8_t groupId) const noexcept;
  void applyViewControl(const io::cigi::ViewControl& control);
  void applyViewDefinition(const io::cigi::ViewDefinition& definition);
  void updateEntitySample(const io::cigi::EntityControl& entity, TimePoint arrival);
  void publishEntities();          // mEntitySamples to the render loop's copy
  void publishSun(TimePoint now);  // the celestial clock's sun over the database's centre to mSun
  void applyOwnship(const io::cigi::EntityControl& entity, const io::cigi::RateControl* rates, double hostTimeS,
                    TimePoint arrival, std::uint32_t hostFrame);
  // A height request whose answer waits for the full-resolution tiles under its point.
  struct PendingHeight {
    io::cigi::HatHotRequest request;
    std::optional<glm::dvec3> pointM;  ///< nothing: not a place this database can answer
    TimePoint deadline;
    std::vector<glm::ivec2> tiles;  ///< the level-0 tiles the answer reads
  };
  void answer(const io::cigi::HatHotRequest& request, TimePoint arrival);
  // A line-of-sight request, reduced to a world ray; it waits like a height request.
  struct PendingLos {
    std::uint16_t losId = 0;
    bool extended = false;
    bool segment = false;  ///< a Segment request (visible = the destination is)
    bool valid = false;    ///< the source (and destination) could be placed
    io::cigi::CoordinateSystem responseSystem = io::cigi::CoordinateSystem::Geodetic;
    std::optional<Pose> responseEntity;       ///< entity-relative answers: the source entity's pose
    std::optional<std::uint16_t> fromEntity;  ///< a ray from an entity does not meet that entity
    std::optional<std::uint16_t> toEntity;    ///< nor a segment to an entity that one (it ends inside it)
    glm::dvec3 fromM{0.0};
    glm::dvec3 direction{0.0};  ///< unit
    double minRangeM = 0.0, maxRangeM = 0.0;
    TimePoint deadline;
    std::vector<glm::ivec2> tiles;  ///< the level-0 tiles under the ray
  };
  void answer(const io::cigi::LosSegmentRequest& request, TimePoint arrival);
  void answer(const io::cigi::LosVectorRequest& request, TimePoint arrival);
  // A request with an update period n > 0 is answered again every n-th field, placed anew each
  // time (an entity-relative point follows its entity), until the host sends its ID again with
  // period 0 or resets the IG. LOS Segment and Vector requests share one ID space, as their
  // responses do.
  template <class Request>
  struct Periodic {
    Request request;
    int fieldsLeft = 0;
  };
  using LosRequest = std::variant<io::cigi::LosSegmentRequest, io::cigi::LosVectorRequest>;
  template <class Request>
  void track(std::map<std::uint16_t, Periodic<Request>>& table, std::uint16_t id, const Request& request,
             std::uint8_t updatePeriod);
  void answerPeriodic(TimePoint now);
  void queueLos(PendingLos pending);
  bool refusedAsBacklog(std::size_t waiting);
  void answerWaitingLos(TimePoint now);
  void respond(const PendingLos& pending);
  // The world pose of entity `entityId` at `at` (0: the ownship; another: its sample extrapolated
  // by its rates, or placed on its parent, as the pictures show it), when known.
  std::optional<Pose> entityPose(std::uint16_t entityId, TimePoint at) const;
  std::optional<glm::dvec3> placePoint(io::cigi::CoordinateSystem system, std::uint16_t entityId, double a, double b,
                                       double c, TimePoint at) const;
  // True when every tile of `tiles` is resident at level 0; asks for the others ahead of the prefetch.
  bool levelZeroResident(const std::vector<glm::ivec2>& tiles);
  void answerWaitingHeights(TimePoint now);
  void respond(const PendingHeight& pending);

  motion::HostMotion& mOwnship;
  // Link thread only (a database switch replaces them).
  core::TileCache* mTerrain;
  std::shared_ptr<core::TileCache> mTerrainOwner;  // after a switch: keeps the database open
  std::shared_ptr<const core::Georeference> mGeoreference;
  std::int8_t mDatabaseNumber;
  HostDatabases* mDatabases = nullptr;
  const Clock& mClock;
  std::atomic<io::cigi::IgMode> mMode{io::cigi::IgMode::Operate};

  // Link thread only.
  HostView mView;
  EntityScene mEntityScene;
  std::vector<core::EntityInstance> mEntityScratch;
  std::optional<FrustumAngles> mFrustum;  // the host's View Definition so far (nothing: the configured one)
  bool mSmoothing = true;                 // IG Control's extrapolation/interpolation enable, as last received
  bool mHaveTime = false;
  std::uint32_t mLastTicks = 0;
  double mHostTimeS = 0.0;
  std::map<std::uint16_t, io::cigi::EntityControl> mEntities;  // active entities other than the ownship
  std::map<std::uint16_t, HostEntitySample> mEntitySamples;    // the detached ones placed, with their rates
  std::vector<PendingHeight> mHeightsWaiting;
  std::vector<io::cigi::HatHotResponse> mHatHotDue;
  std::vector<io::cigi::HatHotExtendedResponse> mHatHotExtendedDue;
  std::vector<PendingLos> mLosWaiting;
  std::vector<io::cigi::LosResponse> mLosDue;
  std::vector<io::cigi::LosExtendedResponse> mLosExtendedDue;
  std::map<std::uint16_t, Periodic<io::cigi::HatHotRequest>> mPeriodicHeights;
  std::map<std::uint16_t, Periodic<LosRequest>> mPeriodicLos;
  CelestialClock mCelestial{0.0};
  TimePoint mSunPublishedAt{};

  std::atomic<std::uint64_t> mOwnshipUpdates{0}, mHatHotRequests{0}, mHatHotAnswered{0}, mLosRequests{0}, mLosHits{0},
      mOtherEntities{0}, mModeChanges{0}, mViewControls{0}, mViewControlsIgnored{0}, mViewDefinitions{0},
      mViewDefinitionsIgnored{0}, mPeriodicRequests{0}, mPeriodicAnswers{0}, mPeriodicRefused{0}, mCelestialControls{0},
      mCelestialRefused{0}, mRequestsRefused{0};
  std::atomic<std::uint32_t> mLastHostFrame{0};
  std::atomic<double> mHazeRangeM{0.0};
  SeqLock<std::optional<core::SunDirection>> mSun;
  mutable std::mutex mPublishedMutex;  // the render loop's copy of mEntitySamples
  std::vector<HostEntitySample> mPublishedEntities;
};

}  // namespace fieldcast::app
