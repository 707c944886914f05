#include <motion/FlightModel.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

namespace fieldcast::motion {
namespace {

constexpr TimePoint at(double seconds) { return TimePoint{Nanoseconds{static_cast<std::int64_t>(seconds * 1e9)}}; }

FlightModelParams steadyParams() {
  FlightModelParams p;
  p.minSpeedMps = p.maxSpeedMps = 100.0;  // throttle does nothing: constant airspeed
  return p;
}

TEST(FlightModel, HandsOffFliesStraightAndLevel) {
  FlightModel model(steadyParams(), Pose{{0, 0, 500}, 0, 0, 0}, 100.0, at(0));
  model.step(at(10), FlightControls{});
  const Pose p = model.state().pose;
  EXPECT_NEAR(p.positionM.y, 1000.0, 1e-6);
  EXPECT_NEAR(p.positionM.x, 0.0, 1e-9);
  EXPECT_NEAR(p.positionM.z, 500.0, 1e-9);
}

TEST(FlightModel, RightStickBanksRightAndTurnsRight) {
  FlightModel model(steadyParams(), Pose{{0, 0, 500}, 0, 0, 0}, 100.0, at(0));
  model.step(at(0.5), FlightControls{0.5, 0, 0, 0.5});  // roll in at 0.75 rad/s for 0.5 s
  model.step(at(10.5), FlightControls{});               // hold the bank
  const FlightState s = model.state();
  EXPECT_NEAR(s.pose.rollRad, 0.375, 1e-9);
  const double expectedRate = 9.80665 * std::tan(0.375) / 100.0;  // coordinated turn
  EXPECT_NEAR(s.headingRateRadS, expectedRate, 1e-12);
  EXPECT_GT(s.pose.headingRad, 10.0 * expectedRate * 0.99);  // turned right (clockwise)
  EXPECT_GT(s.pose.positionM.x, 0.0);                        // drifted east
}

TEST(FlightModel, ExtrapolationMatchesStepping) {
  // In a steady turn the pose predicted 20 ms ahead equals the pose stepped there.
  FlightModel a(steadyParams(), Pose{{0, 0, 500}, 0.3, 0.05, 0.4}, 100.0, at(0));
  FlightModel b(steadyParams(), Pose{{0, 0, 500}, 0.3, 0.05, 0.4}, 100.0, at(0));
  a.step(at(1.0), FlightControls{});
  b.step(at(1.0), FlightControls{});
  const Pose predicted = a.poseAt(at(1.02));
  b.step(at(1.02), FlightControls{});
  const Pose stepped = b.state().pose;
  EXPECT_NEAR(predicted.headingRad, stepped.headingRad, 1e-9);
  EXPECT_NEAR(predicted.positionM.x, stepped.positionM.x, 0.01);  // chord vs arc over 2 m
  EXPECT_NEAR(predicted.positionM.y, stepped.positionM.y, 0.01);
}

TEST(FlightModel, ThrottleSetsAirspeedWithALag) {
  FlightModelParams p;
  p.minSpeedMps = 50.0;
  p.maxSpeedMps = 250.0;
  p.speedTimeConstantS = 2.0;
  FlightModel model(p, Pose{{0, 0, 500}, 0, 0, 0}, 50.0, at(0));
  model.step(at(2.0), FlightControls{0, 0, 0, 1.0});
  EXPECT_NEAR(model.state().speedMps, 250.0 - 200.0 * std::exp(-1.0), 0.01);
}

TEST(FlightModel, NeverGoesBelowTheTerrainClearance) {
  FlightModelParams p = steadyParams();
  p.minClearanceM = 20.0;
  auto ridge = [](double x, double) { return 100.0 + 0.5 * x; };  // rising ground to the east
  FlightModel model(p, Pose{{0, 0, 150}, radians(90.0), radians(-20.0), 0}, 100.0, at(0), ridge);
  for (int i = 1; i <= 400; ++i) {
    model.step(at(i * 0.025), FlightControls{0, -1.0, 0, 0.5});  // full nose-down
    const Pose pose = model.state().pose;
    EXPECT_GE(pose.positionM.z, ridge(pose.positionM.x, 0) + 20.0 - 1e-9);
  }
}

TEST(FlightModel, LimitsBankAndPitch) {
  FlightModelParams p = steadyParams();
  FlightModel model(p, Pose{{0, 0, 3000}, 0, 0, 0}, 100.0, at(0));
  model.step(at(5.0), FlightControls{1.0, 1.0, 0, 0.5});
  EXPECT_NEAR(model.state().pose.rollRad, p.maxBankRad, 1e-12);
  EXPECT_NEAR(model.state().pose.pitchRad, p.maxPitchRad, 1e-12);
  EXPECT_EQ(model.state().rollRateRadS, 0.0);
}

bool samePose(const Pose& a, const Pose& b) {
  // Same arithmetic on the same state gives the same bits; the tolerance only absorbs nothing
  // more than rounding, far below what one 0.2 ms step moves (2 cm, 0.03 mrad).
  constexpr double kM = 1e-9, kRad = 1e-12;
  return std::abs(a.positionM.x - b.positionM.x) <= kM && std::abs(a.positionM.y - b.positionM.y) <= kM &&
         std::abs(a.positionM.z - b.positionM.z) <= kM && std::abs(a.headingRad - b.headingRad) <= kRad &&
         std::abs(a.pitchRad - b.pitchRad) <= kRad && std::abs(a.rollRad - b.rollRad) <= kRad;
}

TEST(FlightModel, PoseAtIsSafeWhileStepping) {
  // One thread steps the model through a rolling, climbing turn; another reads state() and
  // poseAt() all the while. Every state read must be exactly a state the model published (the
  // one a single-threaded run has at that time), in time order; every pose must be the pose a
  // single-threaded run predicts from one of those states, never from an earlier one than the
  // pose before. A torn read (words of two steps), a read of the owner's working copy or a state
  // published before its time matches none of them. Steps are mostly 0.1 ms (one sub-step, so
  // publishing is a large share of the writer's time) and every tenth 20 ms (four sub-steps).
  const FlightModelParams params = steadyParams();
  const Pose start{{0, 0, 500}, 0, 0, 0.2};
  constexpr int kSteps = 20000;
  std::vector<TimePoint> times{at(0)};
  for (int i = 1; i <= kSteps; ++i) times.push_back(times.back() + fromSeconds(i % 10 == 0 ? 0.02 : 0.0001));
  const FlightControls controls{0.1, 0.05, 0.02, 0.5};
  const TimePoint query = at(100.0);  // every pose read asks for the same instant

  // The single-threaded reference: the state after each step, and the pose predicted from it.
  std::vector<FlightState> states;
  std::vector<Pose> predicted;
  {
    FlightModel reference(params, start, 100.0, times[0]);
    states.push_back(reference.state());
    predicted.push_back(reference.poseAt(query));
    for (int i = 1; i <= kSteps; ++i) {
      reference.step(times[static_cast<std::size_t>(i)], controls);
      states.push_back(reference.state());
      predicted.push_back(reference.poseAt(query));
    }
  }

  // The reader records every change it sees in a tight loop (more reads, more chances to meet a
  // write) and the records are checked after the run. The writer never runs more than a few steps
  // ahead of the reader's loop, so the two interleave even when the scheduler runs them in turns.
  FlightModel model(params, start, 100.0, times[0]);
  std::vector<FlightState> seenStates;
  std::vector<Pose> seenPoses;
  seenStates.reserve(2 * states.size());
  seenPoses.reserve(2 * states.size());
  std::atomic<bool> done{false};
  std::atomic<bool> reading{true};
  std::atomic<std::uint64_t> readerLoops{0};
  std::thread reader([&] {
    FlightState lastState = model.state();
    Pose lastPose = model.poseAt(query);
    seenStates.push_back(lastState);
    seenPoses.push_back(lastPose);
    while (!done.load(std::memory_order_relaxed) && seenStates.size() < seenStates.capacity() &&
           seenPoses.size() < seenPoses.capacity()) {
      const FlightState s = model.state();
      if (std::memcmp(&s, &lastState, sizeof s) != 0) seenStates.push_back(lastState = s);
      const Pose p = model.poseAt(query);
      if (std::memcmp(&p, &lastPose, sizeof p) != 0) seenPoses.push_back(lastPose = p);
      readerLoops.fetch_add(1, std::memory_order_relaxed);
    }
    reading = false;
  });
  std::uint64_t loops = 0;
  for (int i = 1; i <= kSteps; ++i) {
    if (i % 8 == 1) {  // wait for the reader to go round once more
      while (readerLoops.load(std::memory_order_relaxed) == loops && reading.load()) std::this_thread::yield();
      loops = readerLoops.load(std::memory_order_relaxed);
    }
    model.step(times[static_cast<std::size_t>(i)], controls);
  }
  done = true;
  reader.join();

  std::size_t badStates = 0, badPoses = 0;
  std::size_t lastIndex = 0;
  for (const FlightState& s : seenStates) {
    const auto it = std::lower_bound(times.begin(), times.end(), s.time);
    const auto i = static_cast<std::size_t>(it - times.begin());
    const bool same = it != times.end() && *it == s.time && i >= lastIndex && samePose(s.pose, states[i].pose) &&
                      s.speedMps == states[i].speedMps && s.rollRateRadS == states[i].rollRateRadS &&
                      s.pitchRateRadS == states[i].pitchRateRadS && s.headingRateRadS == states[i].headingRateRadS;
    if (!same) {
      ++badStates;
      continue;
    }
    lastIndex = i;
  }
  std::size_t k = 0;
  for (const Pose& p : seenPoses) {
    std::size_t j = k;  // from the state of the pose before, onwards
    while (j < predicted.size() && !samePose(p, predicted[j])) ++j;
    if (j == predicted.size()) {
      ++badPoses;
      continue;
    }
    k = j;
  }
  EXPECT_GT(seenStates.size(), 1u);
  EXPECT_EQ(badStates, 0u) << "of " << seenStates.size() << " states read: not a published state, or out of time order";
  EXPECT_EQ(badPoses, 0u) << "of " << seenPoses.size()
                          << " poses read: not predicted from a published state, or from an older one than before";
  // And the model ends exactly where the single-threaded run does.
  EXPECT_TRUE(samePose(model.state().pose, states.back().pose));
}

}  // namespace
}  // namespace fieldcast::motion
