// The host feed in virtual time. Host time is flight time; a datagram sent at host time t arrives
// at IG instant t + delay, and HostMotion places its pose by its own clock estimate (the lower
// envelope of arrival − host time), so the smallest delay becomes a constant bias a real IG has
// too: it cannot know the one-way delay.
#include "PredictedPoses.h"

#include <motion/HostMotion.h>

#include <fieldcast/Conventions.h>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace fieldcast::tools {
namespace {

/// d/dt of the flight's position and (heading, pitch, roll) at `tS`, by a central difference
/// (what a host's Rate Control carries).
void rates(const EvaluatedFlight& flight, double tS, glm::dvec3& velocity, glm::dvec3& angular) {
  constexpr double h = 1e-3;
  const Pose a = flight.poseAtSeconds(std::max(0.0, tS - h));
  const Pose b = flight.poseAtSeconds(tS + h);
  const double dt = tS + h - std::max(0.0, tS - h);
  velocity = (b.positionM - a.positionM) / dt;
  auto wrapped = [](double d) { return std::remainder(d, 2.0 * 3.14159265358979323846); };
  angular = {wrapped(b.headingRad - a.headingRad) / dt, (b.pitchRad - a.pitchRad) / dt,
             wrapped(b.rollRad - a.rollRad) / dt};
}

}  // namespace

std::vector<Pose> predictedFieldPoses(const EvaluatedFlight& flight, const std::vector<warp::FieldTick>& ticks,
                                      const HostFeed& feed) {
  if (ticks.empty()) return {};
  const double lastS = toSeconds(ticks.back().displayTime.time_since_epoch());
  if (lastS > flight.durationS()) throw std::runtime_error("flight '" + flight.name() + "' is too short");
  // Every host frame up to the last field, with its arrival instant
  std::mt19937 rng(feed.seed);
  std::uniform_real_distribution<double> jitter(0.0, feed.jitterMs);
  std::vector<motion::HostSample> samples;
  for (std::uint32_t k = 0;; ++k) {
    const double tS = k / feed.rateHz;
    if (tS > lastS) break;
    motion::HostSample s;
    s.hostTimeS = tS;
    s.hostFrame = k;
    s.pose = flight.poseAtSeconds(tS);
    s.hasRates = true;
    rates(flight, tS, s.velocityMps, s.angularRateRadS);
    s.arrival = TimePoint{fromSeconds(tS + (feed.baseDelayMs + jitter(rng)) * 1e-3)};
    samples.push_back(s);
  }
  // Datagrams are received in arrival order (jitter can swap two: HostMotion drops the older)
  std::stable_sort(samples.begin(), samples.end(),
                   [](const motion::HostSample& a, const motion::HostSample& b) { return a.arrival < b.arrival; });

  motion::HostMotion host;
  std::vector<Pose> poses;
  std::size_t next = 0;
  const Nanoseconds lead = fromSeconds(feed.fieldLeadMs * 1e-3);
  for (const warp::FieldTick& tick : ticks) {
    const TimePoint computed = tick.displayTime - lead;
    while (next < samples.size() && samples[next].arrival <= computed) host.addSample(samples[next++]);
    poses.push_back(host.poseAt(tick.displayTime));
  }
  return poses;
}

PoseError poseError(const Pose& truth, const Pose& predicted) noexcept {
  const glm::dmat3 relative = worldToCameraRotation(truth) * glm::transpose(worldToCameraRotation(predicted));
  const double cosine = std::clamp((relative[0][0] + relative[1][1] + relative[2][2] - 1.0) / 2.0, -1.0, 1.0);
  return {glm::length(truth.positionM - predicted.positionM), std::acos(cosine) * 180.0 / 3.14159265358979323846};
}

}  // namespace fieldcast::tools
