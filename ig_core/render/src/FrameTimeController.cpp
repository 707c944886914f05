// Multiplicative control of the quality knob with a dead band: render cost falls roughly with the
// square of the voxel size far away, so ratios (not differences) are the natural step.
#include <ig_core/FrameTimeController.h>

#include <algorithm>
#include <cmath>

namespace fieldcast::core {

FrameTimeController::FrameTimeController(const FrameTimeControllerConfig& config, double initialQuality) noexcept
    : mConfig(config), mQuality(std::clamp(initialQuality, config.minQuality, config.maxQuality)) {}

double FrameTimeController::update(const RenderedFrame& frame) noexcept {
  const TimePoint from = std::max(frame.submitted, mLastCompleted);
  mLastCompleted = frame.completed;
  // (The grazing rule is compared only when it is the controller's to turn.)
  const bool grazingCurrent = !(mConfig.grazingAnisotropy > 0.0) || frame.maxAnisotropy == maxAnisotropy();
  if (frame.quality != mQuality || !grazingCurrent) return mQuality;
  return update(frame.completed - from);
}

double FrameTimeController::update(Nanoseconds frameTime) noexcept {
  const double target = toSeconds(mConfig.target);
  if (!(target > 0.0)) return mQuality;
  const double t = toSeconds(frameTime);
  mSmoothed = mSmoothed == 0.0 ? t : mSmoothed + std::clamp(mConfig.smoothing, 0.01, 1.0) * (t - mSmoothed);
  const bool canGraze = mConfig.grazingAnisotropy > 0.0;
  if (mSmoothed > target) {
    if (canGraze && !mGrazing) {
      // Over budget: the grazing-angle rule first. The smoothing restarts, since the frames to
      // come cost something else.
      mGrazing = true;
      mGrazingQuality = mQuality;
      mSmoothed = 0.0;
      return mQuality;
    }
    // Over budget: coarsen in proportion to the overrun, bounded per frame. The smoothing
    // restarts: the smoothed time lags, and still over budget once the frames are not, it would
    // coarsen again for them. (Together with skipping stale frames, this took the service's mean
    // knob at a 10 ms target on the bank-turn flight from 7.4 to 5.7, at the same render rate;
    // with noisy frame times it changes the knob more often.)
    mQuality *= std::min(std::sqrt(mSmoothed / target) * 1.02, mConfig.maxStepRatio);
    mSmoothed = 0.0;
  } else if (mSmoothed < mConfig.refineBelow * target) {
    if (mGrazing && mQuality <= mGrazingQuality) {
      // Back where the rule went on: turn it off once there is room for it, else hold.
      if (mSmoothed < mConfig.grazingOffBelow * target) {
        mGrazing = false;
        mSmoothed = 0.0;
      }
      return mQuality;
    }
    mQuality /= mConfig.refineStepRatio;  // well under: refine slowly
    if (mGrazing) mQuality = std::max(mQuality, mGrazingQuality);
  }
  mQuality = std::clamp(mQuality, mConfig.minQuality, mConfig.maxQuality);
  return mQuality;
}

}  // namespace fieldcast::core
