// Host → field latency, end to end: the test is the host of the real `fieldcast` service. It
// holds the ownship still, then turns it by 10° in one host frame, noting on CLOCK_MONOTONIC when
// that datagram left; in what the service emitted it finds the first field whose pose shows the
// turn (its field log) and the first whose pixels do (its video). Cut the host path anywhere and
// no field shows it.
#include "../../tools/latency/EmittedFields.h"
#include "HostTestRig.h"

#include <set>

namespace fieldcast::host_test {
namespace {

double msBetween(std::int64_t fromNs, std::int64_t toNs) { return static_cast<double>(toNs - fromNs) * 1e-6; }

std::int64_t monotonicNs() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

class HostLatency : public HostServiceTest {};

TEST_F(HostLatency, AHostTurnShowsInTheFirstFieldMadeAfterItsDatagram) {
  TestHost host(mPort, cigi::nativeByteOrder());
  host.holdStill();
  startService(5.0, "--field-log " + (mDir / "out/fields.csv").string());
  ASSERT_TRUE(host.waitForIg(30.0)) << "the IG never answered";
  // Two seconds still, then the turn; the datagram's send instant is noted just before it leaves
  std::int64_t turnedNs = 0;
  constexpr std::uint32_t kTurnFrame = 120;
  const Steady::time_point start = Steady::now();
  pace(start, 3.0, [&](std::uint32_t k, double tS) {
    if (k == kTurnFrame) {
      host.turnBy(10.0);
      turnedNs = monotonicNs();
    }
    host.sendFrame(k, tS, tS);
  });
  const nlohmann::json s = finishService();
  ASSERT_FALSE(s.is_null());

  const std::vector<fieldcast::tools::LoggedField> fields =
      fieldcast::tools::readFieldLog((mDir / "out/fields.csv").string());
  ASSERT_GT(fields.size(), 200u);
  // Pose: the first field emitted after the datagram whose heading left the still one
  const auto before =
      std::find_if(fields.rbegin(), fields.rend(), [&](const auto& f) { return f.emittedNs < turnedNs; });
  ASSERT_NE(before, fields.rend());
  const double stillHeading = before->headingDeg;
  const auto byPose = std::find_if(fields.begin(), fields.end(), [&](const auto& f) {
    return f.emittedNs > turnedNs && std::abs(f.headingDeg - stillHeading) > 1e-6;
  });
  ASSERT_NE(byPose, fields.end()) << "no field shows the host's turn: the host path is cut";
  EXPECT_NEAR(std::remainder(byPose->headingDeg - stillHeading, 360.0), 10.0, 0.5);
  const double poseLatencyMs = msBetween(turnedNs, byPose->emittedNs);

  // Pixels (progressive grey: a frame of the video is a field): the first frame after the turn
  // that differs from the one before it by more than any two frames did while the ownship stood
  // still. A 10° turn of a 60° view moves the picture by a sixth of its width.
  const std::vector<Bytes> frames = framesOfVideo();
  const std::uint64_t poseField = byPose->number;
  ASSERT_GT(frames.size(), poseField + 5);
  auto change = [&](std::uint64_t k) {
    double sum = 0.0;
    for (std::size_t i = 0; i < frames[k].size(); ++i) sum += std::abs(frames[k][i] - frames[k - 1][i]);
    return sum / static_cast<double>(frames[k].size());
  };
  // (Pairs across a missed field are left out: after a stall of the machine the picture jumps by
  // the flight of the whole stall.)
  std::set<std::uint64_t> emitted;
  for (const auto& f : fields) emitted.insert(f.number);
  double steady = 0.0;
  for (std::uint64_t k = std::max<std::uint64_t>(poseField, 61) - 60; k < poseField; ++k)
    if (emitted.count(k) && emitted.count(k - 1)) steady = std::max(steady, change(k));
  std::uint64_t pixelField = poseField;
  while (pixelField < frames.size() && change(pixelField) <= 2.0 * steady + 2.0) ++pixelField;
  const auto pixelRecord =
      std::find_if(fields.begin(), fields.end(), [&](const auto& f) { return f.number == pixelField; });
  ASSERT_NE(pixelRecord, fields.end()) << "the pixels never showed the turn (steady change " << steady << ")";
  // Within three fields, and those the machine's own stalls cost between them (the video repeats
  // a frame for each field missed then)
  const double periodMs = 1000.0 / kFieldRateHz;
  const auto stalledFields = static_cast<std::uint64_t>(
      std::ceil(mStalls->stalledMsBetween(byPose->emittedNs, pixelRecord->emittedNs) / periodMs));
  ASSERT_LT(pixelField, poseField + 3 + stalledFields) << "the pixels were late to show the turn";
  const double pixelLatencyMs = msBetween(turnedNs, pixelRecord->emittedNs);

  // Generous for a shared 2-core machine: 15 fields, and the time the machine itself stood still.
  EXPECT_GT(poseLatencyMs, 0.0);
  EXPECT_LT(poseLatencyMs, 15 * 1000.0 / kFieldRateHz + mStalls->stalledMsBetween(turnedNs, byPose->emittedNs));
  EXPECT_GE(pixelLatencyMs, poseLatencyMs);
  RecordProperty("host_to_pose_field_emitted_ms", std::to_string(poseLatencyMs));
  RecordProperty("host_to_pixel_field_emitted_ms", std::to_string(pixelLatencyMs));
  std::printf(
      "host datagram → first field showing it: pose %.1f ms, pixels %.1f ms (fields %llu and %llu; "
      "steady change %.2f)\n",
      poseLatencyMs, pixelLatencyMs, static_cast<unsigned long long>(poseField),
      static_cast<unsigned long long>(pixelField), steady);
}

}  // namespace
}  // namespace fieldcast::host_test
