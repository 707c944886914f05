#pragma once
// Holds the render time near a target by turning the quality knob (RenderSettings::quality) with
// hysteresis: coarsen when the smoothed frame time is over budget, refine only when it is well
// under, and do nothing in between, so the knob does not hunt as the view sweeps.

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
};

/// Turns measured frame times into a quality knob. Not thread-safe; RT-safe (no allocation).
class FrameTimeController {
 public:
  explicit FrameTimeController(const FrameTimeControllerConfig& config, double initialQuality = 1.0) noexcept;

  /// Feeds the time the last frame took; returns the knob to use for the next frame.
  double update(Nanoseconds frameTime) noexcept;
  double quality() const noexcept { return mQuality; }
  /// Smoothed frame time in seconds (0 before the first update).
  double smoothedSeconds() const noexcept { return mSmoothed; }

 private:
  FrameTimeControllerConfig mConfig;
  double mQuality;
  double mSmoothed = 0.0;
};

}  // namespace fieldcast::core
