#pragma once
// The motion model of DESIGN.md §4: anything that answers the camera pose at any instant, past or
// future. The PRP asks it for the pose at every field's display time; the renderer asks it for
// the pose of the frame it is about to render.

#include <fieldcast/Pose.h>
#include <fieldcast/Time.h>

namespace fieldcast::motion {

/// A source of poses over time. Implementations are thread-safe; poseAt is RT-safe.
class MotionSource {
 public:
  virtual ~MotionSource() = default;
  /// The pose at instant `t` (world metres, radians). Thread-safe, RT-safe.
  virtual Pose poseAt(TimePoint t) const noexcept = 0;
};

}  // namespace fieldcast::motion
