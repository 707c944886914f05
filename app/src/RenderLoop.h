#pragma once
// The render thread (DESIGN.md §5): renders frames as fast as the view allows (or at a capped
// rate) for the pose predicted at the time each frame will be ready, keeps two frames in flight
// so the workers never wait for each other, and hands each finished frame to the field thread
// through the triple buffer. The field thread never waits for it.

#include "SceneEntities.h"

#include <service/ServiceMetrics.h>

#include <fieldcast/Intrinsics.h>
#include <fieldcast/SeqLock.h>
#include <fieldcast/Time.h>
#include <ig_core/FrameTimeController.h>
#include <ig_core/Renderer.h>
#include <ig_core/TileCache.h>
#include <motion/MotionSource.h>
#include <prp_warp/TripleBuffer.h>

#include <glm/vec3.hpp>

#include <atomic>

namespace fieldcast::app {

/// Pacing of the render loop.
struct RenderPacing {
  double maxRateHz = 0.0;                      ///< 0: free-running; otherwise frames start no more often than this
  core::FrameTimeControllerConfig controller;  ///< target 0: fixed quality
  double initialQuality = 1.0;
  /// When set and > 0: the haze range (m) of the frames submitted from then on (the CIGI host's
  /// visibility, HostSession::hazeRangeM); read before each frame.
  const std::atomic<double>* hazeRangeM = nullptr;
  /// When set and holding a sun: the sun of the frames submitted from then on (the CIGI host's
  /// time of day, HostSession::sun); read before each frame.
  const SeqLock<std::optional<core::SunDirection>>* sun = nullptr;
  /// When set: the display window's frustum for the frames submitted from then on (the CIGI
  /// host's View Definition); read before each frame. Its size must stay the display's.
  const SeqLock<Intrinsics>* display = nullptr;
  /// When set: the moving entities, posed for each frame's instant and drawn into it.
  const SceneEntities* entities = nullptr;
  /// Each frame gets its flicker-filtered copy (warp::makeFlickerFiltered) before it is handed
  /// over: for a field warper that filters, which then has nothing to filter on the field thread.
  bool flickerFilter = false;
};

/// A database switch (Channel::switchTerrain): the render loop renders each frame from `wanted`
/// once it is set, and publishes in `settled` the terrain of the newest finished frame — once
/// that is the new one, no frame of the old terrain is in flight any more and it may be closed.
struct TerrainSwitch {
  std::atomic<core::TileCache*> wanted{nullptr};
  std::atomic<const core::TileCache*> settled{nullptr};
};

class RenderLoop {
 public:
  /// Every reference must outlive the loop. With a tile cache, each frame first asks it to
  /// prefetch the view's footprint ahead of the motion and holds a lease on its tiles while the
  /// frame is rendered; without one (a fully resident terrain) neither is needed. With a
  /// `terrainSwitch`, frames are rendered from the terrain it wants (see TerrainSwitch).
  RenderLoop(core::Renderer& renderer, const motion::MotionSource& motion, const Intrinsics& display,
             warp::FrameHandover& frames, ServiceMetrics& metrics, const RenderPacing& pacing,
             core::TileCache* tiles = nullptr, TerrainSwitch* terrainSwitch = nullptr);

  /// Renders until `stop` is set. Render thread body; catches and logs, returning false on a
  /// fatal error (after setting `stop`).
  bool run(std::atomic<bool>& stop) noexcept;

  /// Frames handed over so far (any thread): the service waits for the first before it starts
  /// the field clock.
  std::uint64_t framesPublished() const noexcept { return mPublished.load(std::memory_order_acquire); }

 private:
  /// A frame being rendered and the lease that keeps its tiles alive.
  struct InFlight {
    core::Renderer::Ticket ticket;
    core::FrameLease lease;
    const core::TileCache* tiles = nullptr;  // the terrain it is rendered from
  };
  InFlight submitNext(TimePoint now);
  void finish(InFlight& frame);
  void publish(Frame&& frame, const core::RenderStats& stats);

  core::Renderer& mRenderer;
  const motion::MotionSource& mMotion;
  Intrinsics mDisplay;
  warp::FrameHandover& mFrames;
  ServiceMetrics& mMetrics;
  RenderPacing mPacing;
  core::TileCache* mTiles;
  TerrainSwitch* mSwitch;
  core::FrameTimeController mController;
  Nanoseconds mExpectedLatency{std::chrono::milliseconds(50)};  // submit → frame ready, smoothed
  std::uint64_t mNextFrameNumber = 1;
  std::atomic<std::uint64_t> mPublished{0};
};

}  // namespace fieldcast::app
