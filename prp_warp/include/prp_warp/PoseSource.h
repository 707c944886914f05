#pragma once
// Where the PRP gets the pose of every field (DESIGN.md §4): either the motion model answers
// pose(t) directly, or a predictor extrapolates a history of timed poses to t.

#include <motion/MotionSource.h>

#include <fieldcast/Pose.h>
#include <fieldcast/Time.h>

#include <array>
#include <cstddef>
#include <functional>

namespace fieldcast::warp {

/// Anything that answers the camera pose at instant t (world metres, radians).
class PoseSource {
 public:
  virtual ~PoseSource() = default;
  /// Pose at instant `t`. RT-safe in every implementation here.
  virtual Pose pose(TimePoint t) const noexcept = 0;
};

/// Adapts a function (or a motion model) into a PoseSource. The function must not throw and,
/// for use on the field thread, must not allocate or block.
class FunctionPoseSource final : public PoseSource {
 public:
  /// Wraps `fn`. Allocates (std::function) at construction only.
  explicit FunctionPoseSource(std::function<Pose(TimePoint)> fn) : mFn(std::move(fn)) {}
  /// Asks `motion` (which must outlive this object) for every pose.
  explicit FunctionPoseSource(const motion::MotionSource& motion)
      : mFn([m = &motion](TimePoint t) noexcept { return m->poseAt(t); }) {}

  /// Calls the function. RT-safe when the function is.
  Pose pose(TimePoint t) const noexcept override { return mFn(t); }

 private:
  std::function<Pose(TimePoint)> mFn;
};

/// The last few timed poses, newest last. Fixed capacity, never allocates. Not thread-safe:
/// one thread pushes and predicts (publish across threads with a SeqLock).
class PoseHistory {
 public:
  static constexpr std::size_t kCapacity = 3;
  struct Sample {
    TimePoint t{};
    Pose pose;
  };

  /// Appends a sample; a sample not later than the newest replaces it. RT-safe.
  void push(TimePoint t, const Pose& pose) noexcept;
  /// Samples held (0..kCapacity).
  std::size_t size() const noexcept { return mSize; }
  /// Sample `i` back from the newest (0 = newest). `i` < size().
  const Sample& fromNewest(std::size_t i) const noexcept { return mSamples[(mHead + kCapacity - i) % kCapacity]; }
  void clear() noexcept { mSize = 0; }

 private:
  std::array<Sample, kCapacity> mSamples{};
  std::size_t mHead = kCapacity - 1;  // index of the newest sample
  std::size_t mSize = 0;
};

/// Extrapolates the last two poses linearly in time: exact for motion at constant velocity and
/// constant angular rates. Heading and roll are unwrapped, so a turn through north is smooth.
/// With one sample it holds that pose; with none, the default pose.
class ConstantVelocityPredictor final : public PoseSource {
 public:
  /// Adds a timed pose (e.g. from the host at its own rate). RT-safe.
  void push(TimePoint t, const Pose& pose) noexcept { mHistory.push(t, pose); }
  /// Extrapolated (or interpolated) pose at `t`. RT-safe.
  Pose pose(TimePoint t) const noexcept override;
  const PoseHistory& history() const noexcept { return mHistory; }

 private:
  PoseHistory mHistory;
};

/// Fits a parabola in time through the last three poses (Lagrange form): exact for motion at
/// constant acceleration. Falls back to constant velocity with two samples, hold with one.
class ConstantAccelerationPredictor final : public PoseSource {
 public:
  /// Adds a timed pose. RT-safe.
  void push(TimePoint t, const Pose& pose) noexcept { mHistory.push(t, pose); }
  /// Extrapolated pose at `t`. RT-safe.
  Pose pose(TimePoint t) const noexcept override;
  const PoseHistory& history() const noexcept { return mHistory; }

 private:
  PoseHistory mHistory;
};

}  // namespace fieldcast::warp
