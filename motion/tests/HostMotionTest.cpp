// The host motion source against a known flight sent by a simulated host: a clock hours off and
// 100 ppm fast, network jitter with rare spikes (so some datagrams arrive out of order), silences,
// restarts, and readers racing the receiver.
#include <motion/HostClockEstimator.h>
#include <motion/HostMotion.h>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <random>
#include <thread>
#include <vector>

namespace fieldcast::motion {
namespace {

using std::chrono::milliseconds;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// A steady climbing right turn at 100 m/s, 3°/s, through south (heading wraps at ±π).
struct SteadyTurn {
  double speedMps = 100.0;
  double turnRateRadS = radians(3.0);
  double climbMps = 5.0;
  double startHeadingRad = radians(170.0);
  glm::dvec3 centreM{2000.0, -1000.0, 800.0};

  double radiusM() const { return speedMps / turnRateRadS; }
  double headingAt(double tS) const { return startHeadingRad + turnRateRadS * tS; }
  Pose pose(double tS) const {
    const double psi = headingAt(tS);
    // Velocity V·(sin ψ, cos ψ) for heading ψ clockwise from north.
    return Pose{
        {centreM.x - radiusM() * std::cos(psi), centreM.y + radiusM() * std::sin(psi), centreM.z + climbMps * tS},
        std::remainder(psi, kTwoPi),
        std::atan2(climbMps, speedMps),
        std::atan(speedMps * turnRateRadS / 9.80665)};  // coordinated turn
  }
  glm::dvec3 velocity(double tS) const {
    const double psi = headingAt(tS);
    return {speedMps * std::sin(psi), speedMps * std::cos(psi), climbMps};
  }
  glm::dvec3 angleRates() const { return {turnRateRadS, 0.0, 0.0}; }
};

/// The host's clock against the IG's, and the network between them.
struct HostLink {
  TimePoint igStart{std::chrono::seconds{1000}};  // IG instant of the flight's t = 0
  double hostStartS = 5 * 3600.0 + 17.25;         // host clock at that instant: hours off
  double hostDrift = 100e-6;                      // host clock 100 ppm fast
  Nanoseconds minDelay = std::chrono::microseconds{100};
  double jitterMaxS = 0.008;  // uniform 0–8 ms ...
  double spikeS = 0.030;      // ... plus 30 ms on 1 % of datagrams
  double spikeChance = 0.01;

  double hostTimeAt(double flightS) const { return hostStartS + flightS * (1.0 + hostDrift); }
  double flightTimeOf(double hostS) const { return (hostS - hostStartS) / (1.0 + hostDrift); }
  TimePoint igAt(double flightS) const { return igStart + fromSeconds(flightS); }
  double flightSecondsAt(TimePoint t) const { return toSeconds(t - igStart); }
  /// The minimum-delay instant of a host time: what the estimator should find.
  TimePoint idealLocal(double hostS) const { return igAt(flightTimeOf(hostS)) + minDelay; }
};

/// Host samples of `turn` at `rateHz` host frames per second for `durationS`, in arrival order.
std::vector<HostSample> sendFlight(const SteadyTurn& turn, const HostLink& link, double durationS, bool withRates,
                                   bool jitter = true, double rateHz = 60.0, std::uint32_t seed = 19) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<HostSample> out;
  for (std::uint32_t k = 0; k / rateHz <= durationS; ++k) {
    const double hostS = link.hostStartS + k / rateHz;  // the host stamps its own frames
    const double flightS = link.flightTimeOf(hostS);
    double delayS = 0.0;
    if (jitter) {
      delayS = link.jitterMaxS * uniform(random);
      if (uniform(random) < link.spikeChance) delayS += link.spikeS;
    }
    HostSample s;
    s.hostTimeS = hostS;
    s.arrival = link.igAt(flightS) + link.minDelay + fromSeconds(delayS);
    s.pose = turn.pose(flightS);
    s.hasRates = withRates;
    if (withRates) {
      s.velocityMps = turn.velocity(flightS);
      s.angularRateRadS = turn.angleRates();
    }
    s.hostFrame = 1000 + k;
    out.push_back(s);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const HostSample& a, const HostSample& b) { return a.arrival < b.arrival; });
  return out;
}

double positionError(const Pose& a, const Pose& b) { return glm::length(a.positionM - b.positionM); }
double angleErrorDeg(const Pose& a, const Pose& b) {
  return degrees(
      std::max({std::abs(std::remainder(a.headingRad - b.headingRad, kTwoPi)), std::abs(a.pitchRad - b.pitchRad),
                std::abs(std::remainder(a.rollRad - b.rollRad, kTwoPi))}));
}
double errorMs(TimePoint a, TimePoint b) { return std::abs(toSeconds(a - b)) * 1e3; }

TEST(HostMotion, ClockEstimateFindsOffsetAndDriftThroughJitter) {
  const SteadyTurn turn;
  const HostLink link;
  const std::vector<HostSample> samples = sendFlight(turn, link, 20.0, false);
  HostMotion motion;
  EXPECT_EQ(motion.state(link.igStart), HostPoseState::NoSamples);

  double newestHostS = 0.0;
  double worstAfter2sMs = 0.0;
  double worstAheadMs = 0.0;
  for (const HostSample& s : samples) {
    motion.addSample(s);
    newestHostS = std::max(newestHostS, s.hostTimeS);
    if (s.arrival < link.igAt(2.0)) continue;
    // The newest sample's instant, and a field display time 40 ms past it.
    worstAfter2sMs = std::max(worstAfter2sMs, errorMs(motion.toLocal(newestHostS), link.idealLocal(newestHostS)));
    worstAheadMs =
        std::max(worstAheadMs, errorMs(motion.toLocal(newestHostS + 0.04), link.idealLocal(newestHostS + 0.04)));
  }
  const double driftPpm = motion.clockMapping().hostDriftPpm();
  std::printf(
      "[ figures  ] clock offset error from 2 s to 20 s: max %.3f ms (%.3f ms 40 ms ahead); drift %.1f ppm "
      "(true 100)\n",
      worstAfter2sMs, worstAheadMs, driftPpm);
  EXPECT_LT(worstAfter2sMs, 1.0);
  EXPECT_LT(worstAheadMs, 1.0);
  EXPECT_NEAR(driftPpm, 100.0, 20.0);
  EXPECT_GT(motion.counters().reordered, 0u);  // the 30 ms spikes did overtake
}

TEST(HostMotion, ClockEstimateConvergesWithinOneSecond) {
  const HostLink link;
  const std::vector<HostSample> samples = sendFlight(SteadyTurn{}, link, 2.0, false);
  HostClockEstimator clock;
  double worstMs = 0.0;
  double newestHostS = 0.0;
  for (const HostSample& s : samples) {
    if (s.hostTimeS <= newestHostS) continue;  // overtaken by a later one: HostMotion drops these
    newestHostS = s.hostTimeS;
    clock.add(s.hostTimeS, s.arrival);
    if (s.arrival >= link.igAt(1.0))
      worstMs = std::max(worstMs, errorMs(clock.mapping().toLocal(s.hostTimeS), link.idealLocal(s.hostTimeS)));
  }
  std::printf("[ figures  ] clock offset error from 1 s to 2 s: max %.3f ms\n", worstMs);
  EXPECT_LT(worstMs, 1.0);
}

/// The worst pose errors of `motion` fed `samples` against `turn`, measured after the clock's first
/// 2 s: at instants `leads` past the newest sample, and at field display times 10–40 ms after each
/// arrival (the service's case, whose lead past the newest sample also includes the network delay).
struct PoseErrors {
  double pastNewestM = 0, pastNewestDeg = 0, fieldsM = 0, fieldsDeg = 0;
};
PoseErrors flyAndMeasure(const SteadyTurn& turn, const HostLink& link, const std::vector<HostSample>& samples) {
  HostMotion motion;
  PoseErrors e;
  double newestHostS = 0.0;
  for (const HostSample& s : samples) {
    motion.addSample(s);
    newestHostS = std::max(newestHostS, s.hostTimeS);
    if (s.arrival < link.igAt(2.0)) continue;
    const TimePoint newestTrue = link.igAt(link.flightTimeOf(newestHostS));
    for (int leadMs : {16, 20, 25, 29, 33}) {
      const TimePoint t = newestTrue + milliseconds{leadMs};
      const Pose truth = turn.pose(link.flightSecondsAt(t));
      e.pastNewestM = std::max(e.pastNewestM, positionError(motion.poseAt(t), truth));
      e.pastNewestDeg = std::max(e.pastNewestDeg, angleErrorDeg(motion.poseAt(t), truth));
    }
    for (int leadMs : {10, 20, 30, 40}) {
      const TimePoint t = s.arrival + milliseconds{leadMs};
      const Pose truth = turn.pose(link.flightSecondsAt(t));
      e.fieldsM = std::max(e.fieldsM, positionError(motion.poseAt(t), truth));
      e.fieldsDeg = std::max(e.fieldsDeg, angleErrorDeg(motion.poseAt(t), truth));
    }
  }
  return e;
}

TEST(HostMotion, FollowsASteadyTurnWithRates) {
  const SteadyTurn turn;
  const HostLink link;
  const PoseErrors e = flyAndMeasure(turn, link, sendFlight(turn, link, 12.0, true));
  std::printf(
      "[ figures  ] with rates: 16-33 ms past the newest sample max %.4f m %.5f deg; fields 10-40 ms after "
      "arrival max %.4f m %.5f deg (truth: the flight at the IG instant, min delay 0.1 ms included)\n",
      e.pastNewestM, e.pastNewestDeg, e.fieldsM, e.fieldsDeg);
  EXPECT_LT(e.pastNewestM, 0.1);
  EXPECT_LT(e.pastNewestDeg, 0.05);
  EXPECT_LT(e.fieldsM, 0.1);
  EXPECT_LT(e.fieldsDeg, 0.05);
}

TEST(HostMotion, FollowsASteadyTurnWithoutRates) {
  const SteadyTurn turn;
  const HostLink link;
  const PoseErrors e = flyAndMeasure(turn, link, sendFlight(turn, link, 12.0, false));
  std::printf(
      "[ figures  ] without rates: 16-33 ms past the newest sample max %.4f m %.5f deg; fields 10-40 ms after "
      "arrival max %.4f m %.5f deg\n",
      e.pastNewestM, e.pastNewestDeg, e.fieldsM, e.fieldsDeg);
  EXPECT_LT(e.pastNewestM, 0.1);
  EXPECT_LT(e.pastNewestDeg, 0.05);
  EXPECT_LT(e.fieldsM, 0.1);
  EXPECT_LT(e.fieldsDeg, 0.05);
}

TEST(HostMotion, InterpolatesBetweenSamplesOnTheTrack) {
  const SteadyTurn turn;
  HostLink link;
  link.hostDrift = 0.0;
  const std::vector<HostSample> samples = sendFlight(turn, link, 0.2, true, false);
  HostMotion motion;
  for (const HostSample& s : samples) motion.addSample(s);
  double worstM = 0.0, worstDeg = 0.0;
  for (double flightS = 0.1; flightS < 0.19; flightS += 0.0037) {
    const TimePoint t = link.igAt(flightS) + link.minDelay;
    worstM = std::max(worstM, positionError(motion.poseAt(t), turn.pose(flightS)));
    worstDeg = std::max(worstDeg, angleErrorDeg(motion.poseAt(t), turn.pose(flightS)));
  }
  EXPECT_LT(worstM, 1e-4);
  EXPECT_LT(worstDeg, 1e-6);
  // Before the oldest kept sample: the oldest.
  const Pose oldest = motion.poseAt(link.igStart - std::chrono::seconds{5});
  EXPECT_LT(positionError(oldest, turn.pose(0.2 - (HostMotion::kKeptSamples - 1) / 60.0)), 1e-6);
  EXPECT_EQ(oldest, motion.poseAt(link.igStart));
}

TEST(HostMotion, SilentHostExtrapolatesThenHolds) {
  const SteadyTurn turn;
  HostLink link;
  HostMotionOptions options;
  HostMotion motion(options);
  for (const HostSample& s : sendFlight(turn, link, 1.0, true)) motion.addSample(s);
  const double newestFlightS = link.flightTimeOf(link.hostStartS + 1.0);
  const TimePoint newest = motion.toLocal(link.hostStartS + 1.0);
  EXPECT_LT(errorMs(newest, link.idealLocal(link.hostStartS + 1.0)), 1.0);
  EXPECT_EQ(motion.state(newest + milliseconds{10}), HostPoseState::Tracking);
  EXPECT_EQ(motion.state(newest + milliseconds{100}), HostPoseState::Extrapolating);
  EXPECT_EQ(motion.state(newest + milliseconds{300}), HostPoseState::Holding);

  const Pose atBound = motion.poseAt(newest + options.maxExtrapolation);
  EXPECT_LT(positionError(atBound, turn.pose(newestFlightS + 0.25)), 0.5);  // ½·a·τ² = 0.16 m off a straight line
  EXPECT_GT(positionError(atBound, motion.poseAt(newest + milliseconds{100})), 10.0);
  EXPECT_EQ(motion.poseAt(newest + milliseconds{400}), atBound);
  EXPECT_EQ(motion.poseAt(newest + std::chrono::seconds{30}), atBound);
}

TEST(HostMotion, ResumesFromTheHeldPoseWithoutAJump) {
  const SteadyTurn turn;
  const HostLink link;
  HostMotionOptions options;
  std::vector<HostSample> samples = sendFlight(turn, link, 4.0, true);
  // The host goes silent from 1 s to 3 s.
  std::erase_if(samples, [&](const HostSample& s) {
    const double flightS = link.flightTimeOf(s.hostTimeS);
    return flightS > 1.0 && flightS < 3.0;
  });
  HostMotion motion(options);
  std::size_t next = 0;
  double worstStepM = 0.0, worstStepDeg = 0.0, worstAfterBlendM = 0.0;
  bool sawHolding = false;
  TimePoint resumedAt{};
  std::optional<Pose> previous;
  // A field loop: each millisecond, take what has arrived and ask the pose 20 ms ahead.
  for (TimePoint now = link.igAt(0.5); now < link.igAt(4.0); now += milliseconds{1}) {
    for (; next < samples.size() && samples[next].arrival <= now; ++next) {
      if (resumedAt == TimePoint{} && link.flightTimeOf(samples[next].hostTimeS) > 2.0) {
        resumedAt = samples[next].arrival;
        // Instants up to resumeLead ahead may have been shown held already: they keep that pose.
        const Pose held = motion.poseAt(resumedAt);
        const Pose heldAhead = motion.poseAt(resumedAt + options.resumeLead);
        motion.addSample(samples[next]);
        EXPECT_LT(positionError(motion.poseAt(resumedAt), held), 1e-6);
        EXPECT_LT(positionError(motion.poseAt(resumedAt + options.resumeLead), heldAhead), 1e-6);
      } else {
        motion.addSample(samples[next]);
      }
    }
    sawHolding |= motion.state(now) == HostPoseState::Holding;
    const Pose pose = motion.poseAt(now + milliseconds{20});
    if (previous) {
      worstStepM = std::max(worstStepM, positionError(pose, *previous));
      worstStepDeg = std::max(worstStepDeg, angleErrorDeg(pose, *previous));
    }
    previous = pose;
    if (resumedAt != TimePoint{} && now > resumedAt + options.resumeLead + options.resumeBlend) {
      worstAfterBlendM =
          std::max(worstAfterBlendM, positionError(pose, turn.pose(link.flightSecondsAt(now + milliseconds{20}))));
    }
  }
  std::printf(
      "[ figures  ] resuming after 2 s of silence: largest pose step between 1 ms apart fields %.3f m %.4f deg; "
      "after the blend max error %.4f m\n",
      worstStepM, worstStepDeg, worstAfterBlendM);
  EXPECT_TRUE(sawHolding);
  EXPECT_NE(resumedAt, TimePoint{});
  EXPECT_LT(worstStepM, 2.0);  // a 180 m gap spread over 200 ms; no blend would jump it at once
  EXPECT_LT(worstStepDeg, 0.1);
  EXPECT_LT(worstAfterBlendM, 0.1);
}

/// Samples 1/60 s apart with rates, no jitter, no drift.
std::vector<HostSample> cleanFlight(const SteadyTurn& turn, const HostLink& link, double durationS) {
  HostLink clean = link;
  clean.hostDrift = 0.0;
  return sendFlight(turn, clean, durationS, true, false);
}

TEST(HostMotion, DropsAndCountsReorderedSamples) {
  const SteadyTurn turn;
  const HostLink link;
  const std::vector<HostSample> s = cleanFlight(turn, link, 0.15);  // 10 samples
  HostMotion reordered, reference;
  for (int k : {0, 1, 2, 3, 4, 5, 7, 6, 8}) {
    HostSample late = s[k];
    if (k == 6) late.arrival = s[7].arrival + milliseconds{1};  // overtaken by 7
    reordered.addSample(late);
  }
  for (int k : {0, 1, 2, 3, 4, 5, 7, 8}) reference.addSample(s[k]);
  const HostMotion::Counters c = reordered.counters();
  EXPECT_EQ(c.reordered, 1u);
  EXPECT_EQ(c.accepted, 8u);
  EXPECT_EQ(c.restarts, 0u);
  EXPECT_EQ(c.duplicates, 0u);
  for (double flightS : {0.06, 0.1, 0.11, 0.13, 0.2}) {
    EXPECT_EQ(reordered.poseAt(link.igAt(flightS)), reference.poseAt(link.igAt(flightS))) << flightS;
  }
}

TEST(HostMotion, DropsAndCountsDuplicates) {
  const SteadyTurn turn;
  const HostLink link;
  const std::vector<HostSample> s = cleanFlight(turn, link, 0.1);
  HostMotion motion;
  for (int k = 0; k < 4; ++k) motion.addSample(s[k]);
  const Pose before = motion.poseAt(link.igAt(0.08));
  HostSample again = s[3];
  again.arrival += milliseconds{2};
  again.pose.positionM.x += 50.0;  // a different pose at the same host time must not win
  motion.addSample(again);
  EXPECT_EQ(motion.counters().duplicates, 1u);
  EXPECT_EQ(motion.counters().accepted, 4u);
  EXPECT_EQ(motion.poseAt(link.igAt(0.08)), before);
}

TEST(HostMotion, HostClockJumpingBackIsARestart) {
  const SteadyTurn turn;
  const HostLink link;
  HostMotion motion;
  for (const HostSample& s : sendFlight(turn, link, 2.0, true)) motion.addSample(s);
  const HostMotion::Counters before = motion.counters();

  // The host restarts 0.5 s later: its clock from 12 s, another place.
  SteadyTurn elsewhere = turn;
  elsewhere.centreM += glm::dvec3{5000.0, 0.0, 0.0};
  HostLink restarted = link;
  restarted.igStart = link.igAt(2.5);
  restarted.hostStartS = 12.0;
  std::vector<HostSample> second = sendFlight(elsewhere, restarted, 1.0, true);
  for (HostSample& s : second) s.hostFrame += 200;  // frame numbers go on: the clock alone tells
  motion.addSample(second[0]);
  EXPECT_EQ(motion.counters().restarts, 1u);
  EXPECT_EQ(motion.counters().reordered, before.reordered);  // not mistaken for a late datagram
  EXPECT_EQ(motion.counters().accepted, before.accepted + 1);
  // The new track at once (no blend from the old place), and the clock estimate starts again.
  EXPECT_LT(positionError(motion.poseAt(second[0].arrival), second[0].pose), 1e-6);
  EXPECT_EQ(motion.toLocal(second[0].hostTimeS), second[0].arrival);
  for (std::size_t k = 1; k < second.size(); ++k) motion.addSample(second[k]);
  EXPECT_EQ(motion.counters().restarts, 1u);
  const TimePoint t = restarted.igAt(0.9);
  EXPECT_LT(positionError(motion.poseAt(t), elsewhere.pose(0.9)), 0.1);
}

TEST(HostMotion, FrameNumberFallingBackIsARestart) {
  const SteadyTurn turn;
  const HostLink link;
  std::vector<HostSample> s = cleanFlight(turn, link, 0.5);
  HostMotion motion;
  for (std::size_t k = 0; k < 20; ++k) motion.addSample(s[k]);
  s[20].hostFrame = 3;  // host time goes on, the frame counter starts again
  motion.addSample(s[20]);
  EXPECT_EQ(motion.counters().restarts, 1u);
  EXPECT_EQ(motion.clockMapping().hostRefS, s[20].hostTimeS);  // the estimate restarted from this sample
  s[21].hostFrame = 4;
  motion.addSample(s[21]);
  EXPECT_EQ(motion.counters().restarts, 1u);  // counting on from the new number is no restart
  EXPECT_EQ(motion.counters().accepted, 22u);
}

TEST(HostMotion, HostClockJumpingForwardIsARestart) {
  const SteadyTurn turn;
  const HostLink link;
  std::vector<HostSample> s = cleanFlight(turn, link, 0.5);
  HostMotion motion;
  for (std::size_t k = 0; k < 20; ++k) motion.addSample(s[k]);
  s[20].hostTimeS += 10.0;  // 10 s of host time in 17 ms of IG time: a clock step
  motion.addSample(s[20]);
  EXPECT_EQ(motion.counters().restarts, 1u);
  EXPECT_EQ(motion.toLocal(s[20].hostTimeS), s[20].arrival);
}

TEST(HostMotion, CountsAndDropsNonFiniteSamples) {
  const std::vector<HostSample> s = cleanFlight(SteadyTurn{}, HostLink{}, 0.1);
  HostMotion motion, reference;
  motion.addSample(s[0]);
  reference.addSample(s[0]);
  HostSample bad = s[1];
  bad.pose.headingRad = std::nan("");
  motion.addSample(bad);
  bad = s[1];
  bad.velocityMps.y = INFINITY;
  motion.addSample(bad);
  EXPECT_EQ(motion.counters().invalid, 2u);
  EXPECT_EQ(motion.counters().accepted, 1u);
  EXPECT_EQ(motion.poseAt(s[1].arrival), reference.poseAt(s[1].arrival));
}

// After a database switch the host's positions are in another world: the first sample of the
// new history is not interpolated against the last one of the old (which would sweep the camera
// across the gap), and the clock estimate carries on.
TEST(HostMotion, ANewHistoryIsNotInterpolatedAgainstTheOldOne) {
  const SteadyTurn turn;
  HostLink link;
  link.hostDrift = 0.0;
  std::vector<HostSample> samples = sendFlight(turn, link, 1.0, true, false);
  HostMotion motion;
  for (const HostSample& s : samples) motion.addSample(s);
  const std::uint64_t restarts = motion.counters().restarts;

  HostSample moved = samples.back();
  const double stepS = 1.0 / 60.0;
  moved.hostTimeS += stepS;
  moved.arrival += fromSeconds(stepS);
  moved.hostFrame += 1;
  moved.pose.positionM += glm::dvec3{5000.0, -3000.0, 0.0};  // the same flight in the new database
  motion.startNewHistory();
  motion.addSample(moved);

  // Half-way between the old newest sample and the new one: before the new history begins, so
  // its first sample as it is — not the mid-point of a 5.8 km jump.
  const TimePoint between = samples.back().arrival + fromSeconds(stepS / 2);
  EXPECT_LT(glm::length(motion.poseAt(between).positionM - moved.pose.positionM), 0.01);
  EXPECT_EQ(motion.counters().restarts, restarts) << "a new history is not a host restart";
  EXPECT_EQ(motion.sampleUsedAt(between).hostFrame, moved.hostFrame);
}

TEST(HostMotion, NoSamplesGivesTheInitialPose) {
  const Pose initial{{1.0, 2.0, 300.0}, 0.5, 0.1, 0.0};
  const HostMotion motion({}, initial);
  EXPECT_EQ(motion.poseAt(TimePoint{std::chrono::seconds{5}}), initial);
  EXPECT_EQ(motion.state(TimePoint{}), HostPoseState::NoSamples);
}

// The sample a pose was made from: the newest when extrapolating, the later of the pair when
// interpolating, the oldest before the history; and moving that sample moves the pose (the
// record names a sample the pose really depends on).
TEST(HostMotion, SaysWhichSampleAPoseWasMadeFrom) {
  const SteadyTurn turn;
  HostLink link;
  link.hostDrift = 0.0;
  const std::vector<HostSample> samples = sendFlight(turn, link, 0.2, true, false);  // 13 samples, in order
  HostMotion motion;
  EXPECT_FALSE(motion.sampleUsedAt(link.igStart).valid);
  for (const HostSample& s : samples) motion.addSample(s);
  const HostSample& newest = samples.back();
  const auto usedIs = [](const HostSampleUsed& used, const HostSample& s) {
    return used.valid && used.hostFrame == s.hostFrame && used.arrival == s.arrival && used.hostTimeS == s.hostTimeS;
  };
  // After the newest sample: extrapolated from it.
  EXPECT_TRUE(usedIs(motion.sampleUsedAt(link.idealLocal(newest.hostTimeS) + milliseconds{30}), newest));
  EXPECT_TRUE(usedIs(motion.sampleUsedAt(link.idealLocal(newest.hostTimeS)), newest));
  // Between samples 10 and 11: made from both, 11 the newer.
  const HostSample& a = samples[10];
  const HostSample& b = samples[11];
  const TimePoint between = link.idealLocal(a.hostTimeS) + milliseconds{5};
  EXPECT_TRUE(usedIs(motion.sampleUsedAt(between), b));
  // Before the kept history: the oldest kept.
  const HostSample& oldestKept = samples[samples.size() - HostMotion::kKeptSamples];
  EXPECT_TRUE(usedIs(motion.sampleUsedAt(link.igStart - std::chrono::seconds{1}), oldestKept));

  // The same samples with b moved 1 m east: the pose between a and b moves, the one before a does not.
  HostMotion moved;
  for (HostSample s : samples) {
    if (s.hostFrame == b.hostFrame) s.pose.positionM.x += 1.0;
    moved.addSample(s);
  }
  EXPECT_GT(positionError(moved.poseAt(between), motion.poseAt(between)), 0.1);
  const TimePoint beforeA = link.idealLocal(samples[9].hostTimeS) + milliseconds{5};
  EXPECT_EQ(moved.poseAt(beforeA), motion.poseAt(beforeA));
  EXPECT_TRUE(usedIs(motion.sampleUsedAt(beforeA), a));
}

// One receiver thread adds samples of a climbing turn as fast as it can while two readers ask for
// poses inside the kept history: every pose must lie on the helix (its height says where along it,
// the rest must agree) and not behind the instant asked. A torn snapshot mixes samples, or a
// sample's time with another's pose, and leaves it. Also runs under ThreadSanitizer.
TEST(HostMotion, ConcurrentReadersNeverSeeATornPose) {
  const SteadyTurn turn;
  HostLink link;
  link.hostDrift = 0.0;
  const std::vector<HostSample> samples = sendFlight(turn, link, 400.0, true, false);  // 24001 samples
  HostMotion motion;
  std::atomic<int> published{-1};
  std::atomic<bool> done{false};
  std::atomic<long> reads{0}, offTrack{0};

  auto reader = [&](int seed) {
    std::mt19937 random(static_cast<std::uint32_t>(seed));
    std::uniform_real_distribution<double> back(0.0, 4.0);
    while (!done.load(std::memory_order_acquire)) {
      const int k = published.load(std::memory_order_acquire);
      if (k < 8) continue;
      const double flightS = (k - back(random)) / 60.0;
      const Pose p = motion.poseAt(link.igAt(flightS) + link.minDelay);
      (void)motion.state(link.igAt(flightS));
      (void)motion.counters();
      // Where along the helix the pose says it is; never behind t (ahead only when t fell before the
      // oldest kept sample because the writer moved on).
      const double alongS = (p.positionM.z - turn.centreM.z) / turn.climbMps;
      const Pose expected = turn.pose(alongS);
      if (positionError(p, expected) > 1e-3 || angleErrorDeg(p, expected) > 1e-4 || alongS < flightS - 1e-6) {
        offTrack.fetch_add(1);
      }
      reads.fetch_add(1);
    }
  };
  std::thread readerA(reader, 1), readerB(reader, 2);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    motion.addSample(samples[k]);
    published.store(static_cast<int>(k), std::memory_order_release);
  }
  done.store(true, std::memory_order_release);
  readerA.join();
  readerB.join();
  std::printf("[ figures  ] %ld concurrent reads, %ld off the track\n", reads.load(), offTrack.load());
  EXPECT_GT(reads.load(), 0);
  EXPECT_EQ(offTrack.load(), 0);
  EXPECT_EQ(motion.counters().accepted, samples.size());
}

}  // namespace
}  // namespace fieldcast::motion
