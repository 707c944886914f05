#pragma once
// Pose prediction (DESIGN.md §4): a history of timed poses (the host's, at its own rate)
// extrapolated to any instant, so the renderer and the PRP can ask a sampled source for the pose
// at a frame's or a field's time like any other MotionSource.

#include <motion/MotionSource.h>

#include <fieldcast/Pose.h>
#include <fieldcast/Time.h>

#include <array>
#include <cstddef>

namespace fieldcast::motion {

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
/// Not thread-safe (unlike most MotionSources): push and ask from one thread, or publish a copy.
class ConstantVelocityPredictor final : public MotionSource {
 public:
  /// Adds a timed pose (e.g. from the host at its own rate). RT-safe.
  void push(TimePoint t, const Pose& pose) noexcept { mHistory.push(t, pose); }
  /// Extrapolated (or interpolated) pose at `t`. RT-safe.
  Pose poseAt(TimePoint t) const noexcept override;
  const PoseHistory& history() const noexcept { return mHistory; }

 private:
  PoseHistory mHistory;
};

/// Fits a parabola in time through the last three poses (Lagrange form): exact for motion at
/// constant acceleration. Falls back to constant velocity with two samples, hold with one.
/// Not thread-safe, as ConstantVelocityPredictor.
class ConstantAccelerationPredictor final : public MotionSource {
 public:
  /// Adds a timed pose. RT-safe.
  void push(TimePoint t, const Pose& pose) noexcept { mHistory.push(t, pose); }
  /// Extrapolated pose at `t`. RT-safe.
  Pose poseAt(TimePoint t) const noexcept override;
  const PoseHistory& history() const noexcept { return mHistory; }

 private:
  PoseHistory mHistory;
};

}  // namespace fieldcast::motion
