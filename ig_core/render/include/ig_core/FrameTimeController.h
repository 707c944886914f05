#pragma once
// Holds the render time near a target by turning the quality knob (RenderSettings::quality) with
// hysteresis: coarsen when the smoothed frame time is over budget, refine only when it is well
// under, and do nothing in between, so the knob does not hunt as the view sweeps.
//
// Optionally it first turns on the grazing-angle level of detail (RenderSettings::maxAnisotropy),
// which coarsens only far terrain seen at low pitch (where the cost is) and keeps the near field
// sharp; `quality`, which coarsens everything, comes second. Refining undoes them in reverse order.

#include <fieldcast/Time.h>

namespace fieldcast::core {

/// Tuning of the frame-time controller.
struct FrameTimeControllerConfig {
  Nanoseconds target{0};          ///< frame time to hold; 0 disables the controller
  double minQuality = 0.5;        ///< finest knob value allowed
  double maxQuality = 16.0;       ///< coarsest knob value allowed
  double refineBelow = 0.75;      ///< refine when the smoothed time < refineBelow × target
  double smoothing = 0.3;         ///< weight of the newest frame in the smoothed time (0..1]
  double maxStepRatio = 1.25;     ///< largest change of the knob per frame (×/÷)
  double refineStepRatio = 1.05;  ///< change of the knob per frame when refining
  /// Anisotropy of the grazing-angle rule the controller turns on before it coarsens `quality`;
  /// 0 = the quality knob alone.
  double grazingAnisotropy = 0.0;
  /// The rule goes off again only when the smoothed time is below this × target (it roughly halves
  /// the cost of low views, so a wider band than refineBelow keeps it from hunting).
  double grazingOffBelow = 0.4;
};

/// A frame as the controller sees it: when it was submitted and completed, and the knobs it was
/// rendered with (RenderStats).
struct RenderedFrame {
  TimePoint submitted{};
  TimePoint completed{};
  double quality = 1.0;
  double maxAnisotropy = 0.0;
};

/// Turns measured frame times into a quality knob. Not thread-safe; RT-safe (no allocation).
class FrameTimeController {
 public:
  explicit FrameTimeController(const FrameTimeControllerConfig& config, double initialQuality = 1.0) noexcept;

  /// Feeds the time the last frame took; returns the knob to use for the next frame.
  double update(Nanoseconds frameTime) noexcept;
  /// The same for a renderer with frames in flight (the service's render loop), fed in the order
  /// the frames complete. Such a frame waits behind the one before, so its submission →
  /// completion time is about two frame times; what it cost is the time from its submission or
  /// the previous completion, whichever is later: the render period when free-running, the
  /// frame's own time when frames do not overlap. A frame rendered with other knobs than the
  /// current ones (submitted before the last change) is not counted: it says nothing of them.
  double update(const RenderedFrame& frame) noexcept;
  double quality() const noexcept { return mQuality; }
  /// RenderSettings::maxAnisotropy to use with quality(): grazingAnisotropy while the controller
  /// has the rule on, else 0.
  double maxAnisotropy() const noexcept { return mGrazing ? mConfig.grazingAnisotropy : 0.0; }
  /// Smoothed frame time in seconds (0 before the first update).
  double smoothedSeconds() const noexcept { return mSmoothed; }

 private:
  FrameTimeControllerConfig mConfig;
  double mQuality;
  double mSmoothed = 0.0;
  bool mGrazing = false;         ///< the grazing-angle rule is on
  double mGrazingQuality = 0.0;  ///< the knob when the rule went on
  TimePoint mLastCompleted{};    ///< of the frame fed last by submission and completion
};

}  // namespace fieldcast::core
