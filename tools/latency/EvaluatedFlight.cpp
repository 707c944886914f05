// The flights of the evaluation. A stick flight is flown once, up front, in 1 ms steps (the
// flight model sub-steps at 5 ms; finer steps only sample it), and its poses are interpolated
// between steps: the evaluation asks for arbitrary instants many times over.
#include "EvaluatedFlight.h"

#include <io_bridge/InputRecording.h>
#include <io_bridge/StickMapper.h>
#include <io_bridge/StickProfile.h>
#include <motion/FlightModel.h>
#include <motion/ScriptedTrajectory.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace fieldcast::tools {
namespace {

constexpr double kStepS = 1e-3;

double lerpAngle(double a, double b, double f) { return a + f * std::remainder(b - a, 2.0 * std::numbers::pi); }

}  // namespace

EvaluatedFlight scriptedFlight(const std::string& path) {
  auto flight = std::make_shared<motion::ScriptedTrajectory>(motion::ScriptedTrajectory::load(path));
  return EvaluatedFlight(flight->name(), flight->durationS(),
                         [flight](double seconds) { return flight->poseAtSeconds(seconds); });
}

EvaluatedFlight stickFlight(const std::string& path, const Pose& start, double startSpeedMps,
                            const core::TerrainView& terrain) {
  const io::InputRecording recording = io::readInputRecording(path);
  if (recording.events.empty()) throw std::runtime_error(path + ": the recording has no events");
  // The recording's frames as control states, on the flight's clock (its first event at 0)
  io::StickMapper mapper(recording.device, io::StickProfile::generic());
  const std::int64_t originNs = recording.events.front().tNs;
  std::vector<std::pair<double, motion::FlightControls>> frames;
  for (const io::InputEvent& e : recording.events) {
    if (!mapper.apply(e)) continue;
    const io::ControlState& s = mapper.state();
    frames.emplace_back(static_cast<double>(e.tNs - originNs) * 1e-9,
                        motion::FlightControls{s.roll, s.pitch, s.yaw, s.throttle});
  }
  if (frames.empty()) throw std::runtime_error(path + ": the recording has no complete frame");
  const double durationS = frames.back().first;

  // Fly it: each step holds the controls of the newest frame at its start
  motion::FlightModel model(motion::FlightModelParams{}, start, startSpeedMps, TimePoint{},
                            [&terrain](double x, double y) { return terrain.heightAtM(x, y); });
  auto poses = std::make_shared<std::vector<Pose>>();
  std::size_t frame = 0;
  for (int k = 0; k * kStepS <= durationS + kStepS; ++k) {
    const double t = k * kStepS;
    while (frame + 1 < frames.size() && frames[frame + 1].first <= t) ++frame;
    if (k > 0) model.step(TimePoint{fromSeconds(t)}, frames[frame].second);
    poses->push_back(model.state().pose);
  }
  const std::string name = std::filesystem::path(path).stem().string();
  return EvaluatedFlight(name, durationS, [poses](double seconds) {
    const double x = std::clamp(seconds / kStepS, 0.0, static_cast<double>(poses->size() - 1));
    const auto i = std::min(static_cast<std::size_t>(x), poses->size() - 2);
    const double f = x - static_cast<double>(i);
    const Pose& a = (*poses)[i];
    const Pose& b = (*poses)[i + 1];
    Pose p;
    p.positionM = a.positionM + f * (b.positionM - a.positionM);
    p.headingRad = lerpAngle(a.headingRad, b.headingRad, f);
    p.pitchRad = a.pitchRad + f * (b.pitchRad - a.pitchRad);
    p.rollRad = lerpAngle(a.rollRad, b.rollRad, f);
    return p;
  });
}

}  // namespace fieldcast::tools
