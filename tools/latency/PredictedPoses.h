#pragma once
// Field poses as a host-driven IG has them: the flight sampled by a host at its frame rate (Entity
// Control with Rate Control's rates), each datagram delayed by the network, and the service's own
// predictor (motion::HostMotion) asked for the pose at each field's display time with only the
// samples that had arrived when the field was computed.

#include <prp_warp/FieldClock.h>
#include "EvaluatedFlight.h"

#include <fieldcast/Pose.h>

#include <vector>

namespace fieldcast::tools {

/// The host and its network.
struct HostFeed {
  double rateHz = 60.0;      ///< host frames per second
  double baseDelayMs = 0.5;  ///< the smallest one-way delay (loopback or a quiet LAN)
  double jitterMs = 4.0;     ///< plus a uniform random delay in [0, jitter)
  unsigned seed = 1;         ///< of the jitter
  double fieldLeadMs = 4.0;  ///< the field is computed this long before its display time (PRP lead)
};

/// The predicted pose of every field of `ticks`. Throws std::runtime_error when the flight is
/// too short for the samples the fields need.
std::vector<Pose> predictedFieldPoses(const EvaluatedFlight& flight, const std::vector<warp::FieldTick>& ticks,
                                      const HostFeed& feed);

/// How far two poses are apart: position (m) and attitude (the angle of the rotation between the
/// two cameras, degrees).
struct PoseError {
  double positionM = 0.0;
  double angleDeg = 0.0;
};
PoseError poseError(const Pose& truth, const Pose& predicted) noexcept;

}  // namespace fieldcast::tools
