#pragma once
// A flight the evaluation flies: a name, how long it lasts and the pose at any flight time.
// Made from a scripted flight file, or from a stick recording flown through the service's stick
// profile and flight model.

#include <ig_core/TerrainView.h>

#include <fieldcast/Pose.h>
#include <fieldcast/Time.h>

#include <functional>
#include <string>

namespace fieldcast::tools {

class EvaluatedFlight {
 public:
  EvaluatedFlight(std::string name, double durationS, std::function<Pose(double)> poseAtSeconds)
      : mName(std::move(name)), mDurationS(durationS), mPoseAtSeconds(std::move(poseAtSeconds)) {}

  const std::string& name() const noexcept { return mName; }
  double durationS() const noexcept { return mDurationS; }
  /// The pose at flight time `seconds`.
  Pose poseAtSeconds(double seconds) const { return mPoseAtSeconds(seconds); }
  /// The pose at instant `t` (the evaluation's clock starts with the flight).
  Pose poseAt(TimePoint t) const { return mPoseAtSeconds(toSeconds(t.time_since_epoch())); }

 private:
  std::string mName;
  double mDurationS;
  std::function<Pose(double)> mPoseAtSeconds;
};

/// A scripted flight file (config/flights/*.toml). Throws std::runtime_error as the loader does.
EvaluatedFlight scriptedFlight(const std::string& path);

/// A stick recording (the `[input] record` format) flown by the service's generic stick profile
/// and flight model from `start` at `startSpeedMps`, with the terrain floor of `terrain`. The name
/// is the file's stem; the flight lasts as long as the recording. Throws std::runtime_error
/// naming the file when it cannot be read.
EvaluatedFlight stickFlight(const std::string& path, const Pose& start, double startSpeedMps,
                            const core::TerrainView& terrain);

}  // namespace fieldcast::tools
