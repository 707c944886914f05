#pragma once
// One display channel (DESIGN.md §1, §7): its view of the ownship (view offset and frustum), the
// render thread that renders frames for it, and its post-rendering processor — warper, field
// clock, field loop — with the sinks its fields go to. The Service owns the channels and what
// they share: the terrain, the ownship's motion, the clock and the figures. A second channel or a
// stereo pair is another Channel with other settings.

#include <service/ServiceConfig.h>
#include <service/ServiceMetrics.h>
#include "ChannelView.h"
#include "FieldLoop.h"
#include "RenderLoop.h"

#include <fieldcast/Conventions.h>
#include <fieldcast/Intrinsics.h>
#include <fieldcast/SeqLock.h>
#include <fieldcast/Time.h>
#include <ig_core/TileCache.h>
#include <io_bridge/SinksConfig.h>
#include <motion/MotionSource.h>
#include <prp_warp/FieldClock.h>
#include <prp_warp/FieldWarper.h>
#include <prp_warp/TripleBuffer.h>

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace fieldcast::app {

/// A channel's own settings.
struct ChannelSettings {
  ChannelView view;
  core::RenderConfig render;
  warp::PrpSettings prp;
  io::StreamFormat output;
  io::SinksConfig sinks;
  ThreadsConfig threads;
};

/// When the field clock starts and how many fields it makes.
struct FieldStart {
  TimePoint t0;                      ///< display time of field 0 (a frame lock's epoch)
  std::uint64_t firstField = 0;      ///< the first field made (a channel joining a lock late: where the others are)
  TimePoint end = TimePoint::max();  ///< no field displayed at or after this is made
  std::uint64_t fieldCount = 0;      ///< at most this many fields of the schedule (emitted or missed); 0: no limit
};

/// What the field thread's warm-up did (DESIGN.md §4: the first field's deadline comes after it).
struct WarmUp {
  TimePoint done;                 ///< when it finished
  double warpMs = 0.0;            ///< the one warp it made
  std::uint64_t frameNumber = 0;  ///< the frame it warped (0: none yet)
};

/// The view settings a service configuration gives its one channel.
ChannelSettings channelSettingsOf(const ServiceConfig& config);

/// The ownship's motion seen from a channel's eye. Thread-safe and RT-safe as the ownship is.
class ViewMotion final : public motion::MotionSource {
 public:
  ViewMotion(const motion::MotionSource& ownship, const ViewOffset& offset) : mOwnship(ownship), mOffset(offset) {}
  Pose poseAt(TimePoint t) const noexcept override { return offsetPose(mOwnship.poseAt(t), mOffset.load()); }
  /// Moves the eye (a host's View Control) for every pose asked from now on: the next frame
  /// renders from it and the fields warp to it. One writer thread; RT-safe.
  void setOffset(const ViewOffset& offset) noexcept { mOffset.store(offset); }
  ViewOffset offset() const noexcept { return mOffset.load(); }

 private:
  const motion::MotionSource& mOwnship;
  SeqLock<ViewOffset> mOffset;
};

class Channel {
 public:
  /// Called from a channel thread that hit a fatal error, with the reason.
  using OnFatal = std::function<void(const std::string& why)>;

  /// Makes the warper and the sinks (not started). Every reference must outlive the channel.
  /// `onKey` receives the live window's keys. Throws std::runtime_error naming what could not be made.
  Channel(const ChannelSettings& settings, core::TileCache& terrain, const motion::MotionSource& ownship, Clock& clock,
          ServiceMetrics& metrics, OnFatal onFatal, std::function<void(int, io::WindowKey)> onKey = {});
  ~Channel();
  Channel(const Channel&) = delete;
  Channel& operator=(const Channel&) = delete;

  /// Opens every output: an unwritable path fails here, before anything runs. Throws.
  void startOutputs();
  /// Where the render loop reads a runtime haze range (HostSession::hazeRangeM; see RenderPacing);
  /// call before startRendering. Null: the configured haze throughout.
  void setHazeRange(const std::atomic<double>* rangeM) noexcept { mHazeRangeM = rangeM; }
  /// Where the render loop reads a runtime sun (HostSession::sun; see RenderPacing). Before start().
  void setSun(const SeqLock<std::optional<core::SunDirection>>* sun) noexcept { mSun = sun; }
  /// The moving entities the render loop draws in every frame (see RenderPacing); call before
  /// startRendering. Null: none.
  void setEntities(const SceneEntities* entities) noexcept { mEntities = entities; }
  /// Moves the channel's eye on the ownship (a host's View Control; one thread). The next frame
  /// renders from it; fields warp to it at once (the warp's fallback covers the cut).
  void setViewOffset(const ViewOffset& offset) noexcept { mMotion.setOffset(offset); }
  ViewOffset viewOffset() const noexcept { return mMotion.offset(); }
  /// Changes the display window's frustum (a host's View Definition; one thread): its size stays
  /// the configured one. The next frame renders it; the warp maps each frame's window to the
  /// output, so the fields follow with that frame.
  void setDisplay(const Intrinsics& display) noexcept { mDisplay.store(display); }
  /// Mirrors the fields from the next one on (CIGI View Definition's mirror mode). Any thread.
  void setMirror(warp::Mirror mirror) noexcept { mWarper->setMirror(mirror); }
  /// Starts the render thread.
  void startRendering();
  /// Renders from `terrain` from the next frame on (a database switch; any thread). The terrain
  /// in use so far must stay open until terrainSettled() is `terrain`.
  void switchTerrain(core::TileCache& terrain) noexcept {
    mTerrainSwitch.wanted.store(&terrain, std::memory_order_release);
  }
  /// The terrain of the newest finished frame (any thread).
  const core::TileCache* terrainSettled() const noexcept {
    return mTerrainSwitch.settled.load(std::memory_order_acquire);
  }
  /// Decides the field clock's start once the field thread is warm (called on that thread).
  using PlanFields = std::function<FieldStart(const WarmUp& warmUp)>;
  /// Starts the field thread. Before any deadline exists it takes its scheduling, prefaults its
  /// stack and warps the newest frame once into a scratch field (code, data and pages warm); then
  /// `plan` says when field 0 is and how many fields to make, and the field clock starts. Returns
  /// once the clock runs (or the thread failed, through onFatal). `beforeField` runs at the start
  /// of every field (RT-safe; may be empty). `pendingInput` may be null (no stick).
  void startFields(PlanFields plan, FieldLoop::BeforeField beforeField, PendingInput* pendingInput);

  /// The field clock, once the fields have started (the external sync disciplines it).
  warp::FieldClock* fieldClock() noexcept { return mFieldClock.get(); }
  /// The live window, when the sinks have one.
  io::WindowSink* window() noexcept { return mWindow; }
  /// False once the field thread has stopped (its last field, or a stop).
  bool fieldsRunning() const noexcept { return !mFieldsDone.load(std::memory_order_acquire); }
  const ChannelSettings& settings() const noexcept { return mSettings; }

  /// Asks the field thread to stop after its current field (any thread).
  void requestStop() noexcept { mStopFields.store(true); }
  /// Stops the field thread, then the render thread, then drains and closes the sinks. Idempotent.
  void stop();
  /// The sinks' figures ("name: N fields, …" a line each).
  std::string sinksSummary() const;
  std::uint64_t sinksDropped() const;

 private:
  void renderMain() noexcept;
  WarmUp warmUp() noexcept;

  ChannelSettings mSettings;
  core::TileCache& mTerrain;
  ViewMotion mMotion;
  SeqLock<Intrinsics> mDisplay;  // the display window's frustum, read by the render loop
  Clock& mClock;
  ServiceMetrics& mMetrics;
  OnFatal mOnFatal;
  warp::FrameHandover mFrames;
  std::unique_ptr<warp::FieldWarper> mWarper;
  std::unique_ptr<io::SinkHub> mSinks;
  io::WindowSink* mWindow = nullptr;
  std::unique_ptr<warp::FieldClock> mFieldClock;
  std::unique_ptr<FieldLoop> mFieldLoop;
  std::thread mRenderThread;
  std::thread mFieldThread;
  std::atomic<bool> mStopRender{false};
  const std::atomic<double>* mHazeRangeM = nullptr;
  const SeqLock<std::optional<core::SunDirection>>* mSun = nullptr;
  const SceneEntities* mEntities = nullptr;
  TerrainSwitch mTerrainSwitch;
  std::atomic<bool> mStopFields{false};
  std::atomic<bool> mFieldsDone{false};
  std::atomic<bool> mFieldClockReady{false};
  bool mSinksStopped = false;
};

}  // namespace fieldcast::app
