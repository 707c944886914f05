#include "FieldLog.h"
#include "FieldLoop.h"

#include <tools/FieldLogReader.h>

#include <fieldcast/Conventions.h>
#include <io_bridge/FieldSink.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace fieldcast::app {
namespace {

using namespace std::chrono_literals;

struct Seen {
  std::mutex mutex;
  std::vector<std::uint64_t> numbers;
  std::vector<FieldParity> parities;
  std::vector<int> meanLuma;
  std::optional<std::uint64_t> scheduleStart;  // what FieldSink::scheduleStarted was told
  std::optional<std::uint64_t> scheduleEnd;    // what FieldSink::scheduleEnded was told
};

class RecordingSink final : public io::FieldSink {
 public:
  explicit RecordingSink(std::shared_ptr<Seen> seen) : mSeen(std::move(seen)) {}
  std::string name() const override { return "recording"; }
  void open(const io::StreamFormat&) override {}
  io::SinkStatus consume(const Field& field) override {
    long sum = 0;
    for (std::size_t b = 1; b < field.image.bytes().size(); b += 2) sum += field.image.bytes()[b];  // UYVY luma
    std::lock_guard lock(mSeen->mutex);
    mSeen->numbers.push_back(field.fieldNumber);
    mSeen->parities.push_back(field.parity);
    mSeen->meanLuma.push_back(static_cast<int>(sum / static_cast<long>(field.image.bytes().size() / 2)));
    return io::SinkStatus::Ok;
  }
  void scheduleStarted(std::uint64_t firstField) override {
    std::lock_guard lock(mSeen->mutex);
    mSeen->scheduleStart = firstField;
  }
  void scheduleEnded(std::uint64_t firstFieldAfter) override {
    std::lock_guard lock(mSeen->mutex);
    mSeen->scheduleEnd = firstFieldAfter;
  }
  void close() override {}

 private:
  std::shared_ptr<Seen> mSeen;
};

// A mid-grey frame of a 64×48 display with margins, seen from a fixed pose over flat ground.
Frame greyFrame(const Pose& pose, TimePoint poseTime) {
  Frame f;
  f.margin = MarginPx{8, 6};
  f.intrinsics = Intrinsics::fromHorizontalFov(80, 60, radians(60.0));
  f.image = Image(80, 60, PixelFormat::Rgb8);
  for (auto& b : f.image.bytes()) b = 128;
  f.pose = pose;
  f.poseTime = poseTime;
  f.frameNumber = 1;
  for (const glm::dvec2& px : controlGridFramePx(64, 48, f.margin)) {
    const glm::dvec3 ray = pixelRay(pose, f.intrinsics, px);
    const double t = pose.positionM.z / -ray.z;  // ground plane z = 0
    f.controlPoints.push_back(ControlPoint{px, pose.positionM + t * ray, ControlPointKind::Surface});
  }
  return f;
}

// A 64×48 UYVY field raster, quadratic warp, the other settings at their defaults.
warp::FieldWarperConfig smallWarper() {
  warp::FieldWarperConfig config;
  config.rasterWidthPx = 64;
  config.rasterHeightPx = 48;
  config.outputFormat = PixelFormat::Uyvy422;
  return config;
}

// A camera that stays where the test puts it.
class FixedPose final : public motion::MotionSource {
 public:
  explicit FixedPose(const Pose& pose) : mPose(pose) {}
  Pose poseAt(TimePoint) const noexcept override { return mPose; }

 private:
  Pose mPose;
};

// A camera the test turns between fields.
class SettablePose final : public motion::MotionSource {
 public:
  explicit SettablePose(const Pose& p) : pose(p) {}
  Pose poseAt(TimePoint) const noexcept override { return pose; }
  Pose pose;
};

struct Rig {
  VirtualClock clock{TimePoint{1s}};
  warp::FieldClockConfig clockConfig;
  std::unique_ptr<warp::FieldClock> fieldClock;
  warp::FieldWarper warper{smallWarper()};
  warp::FrameHandover frames;
  Pose pose{{0, 0, 100}, 0.0, radians(-30.0), 0.0};
  FixedPose poses{pose};
  std::shared_ptr<Seen> seen = std::make_shared<Seen>();
  std::unique_ptr<io::SinkHub> hub;
  ServiceMetrics metrics;

  Rig() {
    fieldClock = std::make_unique<warp::FieldClock>(clock, clockConfig, clock.now() + 10ms);
    io::StreamFormat format;
    format.widthPx = 64;
    format.heightPx = 48;
    format.pixelAspect = {1, 1};
    hub = std::make_unique<io::SinkHub>(format, io::SinkHubOptions{64});
    hub->add(std::make_unique<RecordingSink>(seen));
    hub->start();
  }
};

TEST(FieldLoop, BlackUntilTheFirstFrameThenWarpedFieldsInOrder) {
  Rig rig;
  FieldLoop loop(*rig.fieldClock, rig.clock, rig.warper, rig.frames, rig.poses, *rig.hub, rig.metrics);
  for (int k = 0; k < 4; ++k) loop.emit(rig.fieldClock->next());
  rig.frames.back() = greyFrame(rig.pose, rig.clock.now());
  rig.frames.publish();
  for (int k = 0; k < 6; ++k) loop.emit(rig.fieldClock->next());
  rig.hub->stop();

  ASSERT_EQ(rig.seen->numbers.size(), 10u);
  for (std::uint64_t k = 0; k < 10; ++k) EXPECT_EQ(rig.seen->numbers[k], k);
  EXPECT_EQ(rig.seen->parities[0], FieldParity::Bottom);  // NTSC: bottom field first
  EXPECT_EQ(rig.seen->parities[1], FieldParity::Top);
  EXPECT_LE(rig.seen->meanLuma[3], 17);        // black (video range)
  EXPECT_NEAR(rig.seen->meanLuma[9], 126, 4);  // mid grey through BT.601
  const ServiceFigures f = rig.metrics.figures(rig.clock.now());
  EXPECT_EQ(f.fieldsEmitted, 10u);
  EXPECT_EQ(f.fieldsBlack, 4u);
  EXPECT_EQ(f.frameAge.count, 6u);
  EXPECT_EQ(f.marginViolations, 0u);
}

// Each field's line carries its own margin violations: none at the frame's pose, some once the
// camera has turned past the margins; the lines add up to the service's count.
TEST(FieldLoop, LogsEachFieldsMarginViolations) {
  Rig rig;
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("fieldcast_field_loop_margin_" + std::to_string(getpid()) + ".csv");
  rig.metrics.openFieldLog(path);
  SettablePose camera(rig.pose);
  FieldLoop loop(*rig.fieldClock, rig.clock, rig.warper, rig.frames, camera, *rig.hub, rig.metrics);
  rig.frames.back() = greyFrame(rig.pose, rig.clock.now());
  rig.frames.publish();
  loop.emit(rig.fieldClock->next());
  camera.pose.headingRad += radians(20.0);  // about 19 px at 55 px/rad: the 8-px margin is passed
  loop.emit(rig.fieldClock->next());
  camera.pose.headingRad += radians(10.0);
  loop.emit(rig.fieldClock->next());
  rig.hub->stop();
  rig.metrics.closeFieldLog();

  std::vector<std::uint64_t> marginPx;
  for (const tools::LoggedField& f : tools::readFieldLog(path.string())) marginPx.push_back(f.marginPx);
  std::filesystem::remove(path);
  ASSERT_EQ(marginPx.size(), 3u);
  EXPECT_EQ(marginPx[0], 0u);
  EXPECT_GT(marginPx[1], 0u);
  EXPECT_GT(marginPx[2], marginPx[1]);
  EXPECT_EQ(marginPx[0] + marginPx[1] + marginPx[2], rig.metrics.figures(rig.clock.now()).marginViolations);
}

TEST(FieldLoop, AFieldThatCannotBeMadeIsCountedAndTheScheduleGoesOn) {
  Rig rig;
  FieldLoop loop(*rig.fieldClock, rig.clock, rig.warper, rig.frames, rig.poses, *rig.hub, rig.metrics);
  loop.emit(rig.fieldClock->next());
  rig.clock.advance(50ms);  // a stall: fields 1 and 2 can no longer be made, field 3 can
  const warp::FieldTick tick = rig.fieldClock->next();
  loop.emit(tick);
  rig.hub->stop();
  EXPECT_EQ(tick.fieldNumber, 3u);
  EXPECT_EQ(rig.metrics.figures(rig.clock.now()).fieldsMissed, 2u);
  ASSERT_EQ(rig.seen->numbers.size(), 2u);
  EXPECT_EQ(rig.seen->numbers[1], 3u);  // no burst of late fields
}

TEST(FieldLoop, AFieldHandedOverAfterItsDisplayTimeIsCountedLate) {
  Rig rig;
  FieldLoop loop(*rig.fieldClock, rig.clock, rig.warper, rig.frames, rig.poses, *rig.hub, rig.metrics);
  // Field 1's work starts in time (at its wake-up, the lead before its display time) but takes
  // longer than the lead; fields 0 and 2 take no time.
  loop.setBeforeField([&rig](const warp::FieldTick& tick) {
    if (tick.fieldNumber == 1) rig.clock.advance(rig.clockConfig.lead + 1ms);
  });
  for (int k = 0; k < 3; ++k) loop.emit(rig.fieldClock->next());
  rig.hub->stop();
  const ServiceFigures f = rig.metrics.figures(rig.clock.now());
  EXPECT_EQ(f.fieldsEmitted, 3u);
  EXPECT_EQ(f.fieldsLate, 1u);
  EXPECT_EQ(f.fieldsMissed, 0u);
}

TEST(FieldLoop, RunStopsAtTheEndInstantAsked) {
  Rig rig;
  FieldLoop loop(*rig.fieldClock, rig.clock, rig.warper, rig.frames, rig.poses, *rig.hub, rig.metrics);
  std::atomic<bool> stop{false};
  loop.run(stop, rig.fieldClock->displayTime(30));
  rig.hub->stop();
  EXPECT_EQ(rig.seen->numbers.size(), 30u);
  EXPECT_EQ(rig.seen->scheduleEnd, 30u);
}

TEST(FieldLoop, FieldsMissedAtTheEndOfTheScheduleAreCountedAndTheSinksToldWhereItEnded) {
  // Field 27's work stalls four periods: fields 28–31 can no longer be made; 28 and 29 are the
  // schedule's last (it ends at field 30, by the instant or by the count), 30 and 31 are not in it.
  for (const bool byCount : {false, true}) {
    SCOPED_TRACE(byCount ? "ended by the field count" : "ended by the instant");
    Rig rig;
    FieldLoop loop(*rig.fieldClock, rig.clock, rig.warper, rig.frames, rig.poses, *rig.hub, rig.metrics);
    loop.setBeforeField([&rig](const warp::FieldTick& tick) {
      if (tick.fieldNumber == 27) rig.clock.advance(4 * rig.clockConfig.rate.period());
    });
    std::atomic<bool> stop{false};
    if (byCount)
      loop.run(stop, TimePoint::max(), 30);
    else
      loop.run(stop, rig.fieldClock->displayTime(30));
    rig.hub->stop();
    EXPECT_EQ(rig.seen->numbers.size(), 28u);
    EXPECT_EQ(rig.metrics.figures(rig.clock.now()).fieldsMissed, 2u);
    EXPECT_EQ(rig.seen->scheduleEnd, 30u);
  }
}

TEST(FieldLoop, FieldsMissedBeforeTheFirstOneMadeAreCountedAndTheSinksToldWhereTheScheduleStarts) {
  Rig rig;
  FieldLoop loop(*rig.fieldClock, rig.clock, rig.warper, rig.frames, rig.poses, *rig.hub, rig.metrics);
  rig.clock.advance(50ms);  // a stall before the first field: fields 0–2 can no longer be made
  std::atomic<bool> stop{false};
  loop.run(stop, TimePoint::max(), 10);
  rig.hub->stop();
  EXPECT_EQ(rig.seen->scheduleStart, 0u);
  ASSERT_FALSE(rig.seen->numbers.empty());
  EXPECT_EQ(rig.seen->numbers.front(), 3u);
  EXPECT_EQ(rig.metrics.figures(rig.clock.now()).fieldsMissed, 3u);
  EXPECT_EQ(rig.seen->scheduleEnd, 10u);
}

TEST(FieldLoop, AScheduleEndingOnAMoveOntoAnotherLockEndsAfterTheLastFieldMade) {
  // During the last field (29) the clock hears of a lock that began 1000¼ fields earlier: the tick
  // that ends the run is in that lock's numbering, which no sink has seen.
  Rig rig;
  FieldLoop loop(*rig.fieldClock, rig.clock, rig.warper, rig.frames, rig.poses, *rig.hub, rig.metrics);
  loop.setBeforeField([&rig](const warp::FieldTick& tick) {
    if (tick.fieldNumber == 29) {
      const RationalRate rate = rig.clockConfig.rate;
      rig.fieldClock->lockTo(rig.fieldClock->displayTime(0) - rate.tickOffset(1000) - rate.period() / 4);
    }
  });
  std::atomic<bool> stop{false};
  loop.run(stop, TimePoint::max(), 30);
  rig.hub->stop();
  ASSERT_EQ(rig.seen->numbers.size(), 30u);
  EXPECT_EQ(rig.seen->numbers.back(), 29u);
  EXPECT_EQ(rig.seen->scheduleEnd, 30u);
}

TEST(FieldLoop, AStoppedRunTellsTheSinksNoScheduleEnd) {
  Rig rig;
  FieldLoop loop(*rig.fieldClock, rig.clock, rig.warper, rig.frames, rig.poses, *rig.hub, rig.metrics);
  std::atomic<bool> stop{false};
  loop.setBeforeField([&stop](const warp::FieldTick& tick) {
    if (tick.fieldNumber == 5) stop.store(true);
  });
  loop.run(stop, TimePoint::max(), 30);
  rig.hub->stop();
  EXPECT_EQ(rig.seen->numbers.size(), 6u);
  EXPECT_FALSE(rig.seen->scheduleEnd.has_value());
}

TEST(FieldLoop, RunStopsAfterTheFieldCountAskedMissedOnesIncluded) {
  Rig rig;
  FieldLoop loop(*rig.fieldClock, rig.clock, rig.warper, rig.frames, rig.poses, *rig.hub, rig.metrics);
  // Field 3's work stalls two periods: field 4 can no longer be made, and counts
  loop.setBeforeField([&rig](const warp::FieldTick& tick) {
    if (tick.fieldNumber == 3) rig.clock.advance(2 * rig.clockConfig.rate.period());
  });
  std::atomic<bool> stop{false};
  loop.run(stop, TimePoint::max(), 30);
  rig.hub->stop();
  ASSERT_FALSE(rig.seen->numbers.empty());
  EXPECT_EQ(rig.seen->numbers.back(), 29u);
  EXPECT_EQ(rig.metrics.figures(rig.clock.now()).fieldsMissed, 1u);
  EXPECT_EQ(rig.seen->numbers.size(), 29u);
}

// With a host: each field's record names the newest host sample its pose was made from, and the
// first field made from a sample measures arrival → emission and → display; a field made from
// the same sample again measures nothing.
TEST(FieldLoop, RecordsEachFieldAndTheHostSampleItsPoseCameFrom) {
  Rig rig;
  motion::HostMotion host;
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("fieldcast_field_loop_" + std::to_string(getpid()) + ".csv");
  rig.metrics.openFieldLog(path);
  rig.metrics.setHostSamples(&host);
  FieldLoop loop(*rig.fieldClock, rig.clock, rig.warper, rig.frames, host, *rig.hub, rig.metrics);
  const auto sample = [&](std::uint32_t frame, double eastM) {
    motion::HostSample s;
    s.hostTimeS = 100.0 + frame / 60.0;
    s.arrival = rig.clock.now();
    s.pose = Pose{{eastM, 0.0, 100.0}, 0.0, 0.0, 0.0};
    s.hostFrame = frame;
    host.addSample(s);
    return s.arrival;
  };
  loop.emit(rig.fieldClock->next());  // before any sample
  const TimePoint arrival7 = sample(7, 10.0);
  rig.clock.advance(3ms);
  const warp::FieldTick second = rig.fieldClock->next();
  loop.emit(second);
  loop.emit(rig.fieldClock->next());  // the same sample again
  const TimePoint arrival8 = sample(8, 20.0);
  const warp::FieldTick fourth = rig.fieldClock->next();
  loop.emit(fourth);
  rig.hub->stop();
  rig.metrics.closeFieldLog();

  const ServiceFigures f = rig.metrics.figures(rig.clock.now());
  EXPECT_EQ(f.hostToEmission.count, 2u);
  EXPECT_EQ(f.hostToDisplay.count, 2u);
  EXPECT_EQ(f.fieldLogRecords, 4u);
  EXPECT_EQ(f.fieldLogDropped, 0u);
  const nlohmann::json summary = toJson(f);  // what --summary writes
  EXPECT_EQ(summary["host_to_field_emission"]["count"], 2);
  EXPECT_EQ(summary["field_log"]["records"], 4);
  EXPECT_EQ(summary["field_log"]["dropped"], 0);
  // Fields 1 and 3 were the first made from samples 7 and 8 (within the histogram's 2 % bins).
  const double toDisplayS =
      std::max(toSeconds(second.displayTime - arrival7), toSeconds(fourth.displayTime - arrival8));
  EXPECT_NEAR(f.hostToDisplay.maxS, toDisplayS, 0.02 * toDisplayS);

  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::filesystem::remove(path);
  ASSERT_EQ(lines.size(), 5u);
  const auto hostColumns = [](const std::string& line) {  // the last two: host_frame,host_arrival_ns
    const auto last = line.rfind(',');
    return line.substr(line.rfind(',', last - 1) + 1);
  };
  EXPECT_EQ(hostColumns(lines[1]), ",");
  const std::string arrival7Ns = std::to_string(arrival7.time_since_epoch().count());
  EXPECT_EQ(hostColumns(lines[2]), "7," + arrival7Ns);
  EXPECT_EQ(hostColumns(lines[3]), "7," + arrival7Ns);
  EXPECT_EQ(hostColumns(lines[4]).substr(0, 2), "8,");
  EXPECT_EQ(lines[2].substr(0, 2), "1,");
  EXPECT_NE(lines[2].find(",10.0000,0.0000,100.0000,"), std::string::npos) << lines[2];  // no rates, one sample: held
}

}  // namespace
}  // namespace fieldcast::app
