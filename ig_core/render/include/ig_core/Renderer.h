#pragma once
// The IG's render entry point: a pose and a display window in, a Frame out (image with margins,
// optional range, control points, pose and times). Runs the column caster on a persistent pool.

#include <ig_core/RenderPool.h>
#include <ig_core/RenderSettings.h>
#include <ig_core/TerrainView.h>

#include <fieldcast/Frame.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace fieldcast::core {

struct CasterThread;

/// Work counted while rendering one frame.
struct RenderStats {
  std::uint64_t steps = 0;          ///< height samples (march steps) over all rays
  std::uint64_t rays = 0;           ///< rays cast (pixels × supersampling, and rows cast again)
  std::uint64_t secondaryRays = 0;  ///< rays gone on through a complex stick's see-through texel
  std::uint64_t pixels = 0;
  double quality = 1.0;        ///< the quality knob the frame was rendered with (RenderSettings)
  double maxAnisotropy = 0.0;  ///< its grazing-angle rule (RenderSettings), 0 = off
};

/// Renders frames of one terrain. Submit/finish may be called from one thread at a time; several
/// frames may be in flight, and the workers start the next one while the last columns of the
/// previous one are still being cast.
class Renderer {
 public:
  /// `threads` ≤ 0: one worker per hardware thread. Not RT-safe (starts threads).
  Renderer(const TerrainView& view, const RenderSettings& settings, int threads = 0);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  const RenderSettings& settings() const noexcept { return mSettings; }
  /// New settings apply to frames submitted afterwards (in-flight frames keep theirs).
  void setSettings(const RenderSettings& settings) noexcept { mSettings = settings; }
  /// Only the quality knob (the frame-time controller's output).
  void setQuality(double quality) noexcept { mSettings.quality = quality; }
  /// Grazing-angle level of detail for frames submitted from now on (RenderSettings::maxAnisotropy).
  void setMaxAnisotropy(double anisotropy) noexcept { mSettings.maxAnisotropy = anisotropy; }
  int threads() const noexcept { return mPool.threads(); }
  /// Renders frames submitted from now on from `view` (a database switch). Frames in flight keep
  /// the view they were submitted with, which must outlive them. Not RT-safe (scans the view).
  void setTerrain(const TerrainView& view);

  class InFlight;
  /// Deleting a ticket waits for its frame's columns first (never frees work in progress).
  struct InFlightDeleter {
    void operator()(InFlight* frame) const noexcept;
  };
  /// A frame being rendered.
  using Ticket = std::unique_ptr<InFlight, InFlightDeleter>;

  /// Starts rendering a frame and returns at once. The frame's buffers come from `recycle` (pass
  /// back a frame no longer needed and nothing is allocated) or are allocated.
  Ticket submit(const ViewRequest& request, Frame&& recycle = Frame{});
  /// Waits for a submitted frame and returns it, with its statistics in `stats` if given.
  Frame finish(Ticket frame, RenderStats* stats = nullptr);
  /// submit + finish.
  Frame render(const ViewRequest& request, RenderStats* stats = nullptr, Frame&& recycle = Frame{});

 private:
  const TerrainView* mView;
  RenderSettings mSettings;
  std::uint16_t mCeilingQ;
  std::uint32_t mBaseColourRgba;          // the base plane beyond the terrain's edge
  std::vector<CasterThread> mThreads;     // one per worker
  std::unique_ptr<CasterThread> mCaller;  // for control rays on the submitting thread
  RenderPool mPool;
};

}  // namespace fieldcast::core
