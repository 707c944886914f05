// FieldWarper::produce() end to end, with the global allocator instrumented: the per-field path
// must not allocate (DESIGN.md §5), whatever the warp, parity and post-processing.
#include "AnalyticScene.h"

#include <motion/PosePredictor.h>
#include <prp_warp/FieldWarper.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <new>
#include <vector>

namespace {
std::atomic<long> gAllocations{0};
}  // namespace

void* operator new(std::size_t n) {
  gAllocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
// GCC cannot see that this replaced operator new pairs with these deletes.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace fieldcast::warp {
namespace {

constexpr int kW = 160, kH = 120;  // test::obliqueFrame()'s display window

const Frame& scene() { return test::obliqueFrame(); }

// scene() with its flicker-filtered copy, as a producer hands it over (made once, outside the
// counted calls)
const Frame& sceneWithCopy() {
  static const Frame frame = [] {
    Frame f = scene();
    makeFlickerFiltered(f);
    return f;
  }();
  return frame;
}

class ProduceWithoutAllocating : public ::testing::TestWithParam<WarpKind> {};

TEST_P(ProduceWithoutAllocating, EveryParityAndFormat) {
  for (PixelFormat format : {PixelFormat::Uyvy422, PixelFormat::Rgb8, PixelFormat::Grey8}) {
    FieldWarperConfig cfg;
    cfg.warp = GetParam();
    cfg.rasterWidthPx = 2 * kW;       // scaled output raster
    cfg.rasterHeightPx = 2 * kH + 1;  // odd: the two parities differ in rows
    cfg.outputFormat = format;
    cfg.flickerFilter = true;
    cfg.autoGain.enabled = true;
    cfg.mirror = Mirror::Both;
    cfg.maxFrameWidthPx = 256;
    cfg.maxFrameHeightPx = 256;
    FieldWarper warper(cfg);
    Field field = warper.makeField();
    motion::ConstantVelocityPredictor poses;
    poses.push(TimePoint{}, scene().pose);
    Pose later = scene().pose;
    later.positionM.y += 10.0;
    later.rollRad = 0.05;
    poses.push(TimePoint{Nanoseconds{100'000'000}}, later);

    const Frame& withCopy = sceneWithCopy();  // made before the count
    const long before = gAllocations.load();
    FieldStatus statuses[6];
    for (int k = 0; k < 6; ++k) {
      const FieldSpec spec{static_cast<std::uint64_t>(k), TimePoint{Nanoseconds{100'000'000 + k * 16'683'333}},
                           k % 2 ? FieldParity::Bottom : FieldParity::Top};
      statuses[k] = warper.produce(scene(), poses.poseAt(spec.displayTime), spec, field);
    }
    // A frame with its producer's flicker-filtered copy
    const FieldSpec fromCopy{6, TimePoint{Nanoseconds{190'000'000}}, FieldParity::Top};
    const FieldStatus copyStatus = warper.produce(withCopy, poses.poseAt(fromCopy.displayTime), fromCopy, field);
    const FieldSpec prog{7, TimePoint{Nanoseconds{200'000'000}}, FieldParity::Progressive};
    const FieldStatus progStatus = warper.produce(scene(), poses.poseAt(prog.displayTime), prog, field);
    const long allocations = gAllocations.load() - before;

    EXPECT_EQ(allocations, 0) << toString(GetParam()) << " " << toString(format);
    for (FieldStatus s : statuses) EXPECT_EQ(s, FieldStatus::Ok);
    EXPECT_EQ(progStatus, FieldStatus::Ok);
    EXPECT_EQ(copyStatus, FieldStatus::Ok);
    EXPECT_EQ(field.image.heightPx(), 2 * kH + 1);
    EXPECT_EQ(field.image.format(), format);
    EXPECT_EQ(warper.counters().fields.load(), 8u);
  }
}

INSTANTIATE_TEST_SUITE_P(Kinds, ProduceWithoutAllocating,
                         ::testing::Values(WarpKind::Hold, WarpKind::Rotation, WarpKind::Quadratic,
                                           WarpKind::Homography, WarpKind::Mesh, WarpKind::Range3d),
                         [](const auto& p) { return std::string(toString(p.param)); });

TEST(FieldWarper, NoFrameGivesABlackFieldAndCountsIt) {
  FieldWarperConfig cfg;
  cfg.rasterWidthPx = 64;
  cfg.rasterHeightPx = 48;
  FieldWarper warper(cfg);
  Field field = warper.makeField();
  EXPECT_EQ(warper.produce(Frame{}, Pose{}, FieldSpec{0, TimePoint{}, FieldParity::Top}, field), FieldStatus::NoFrame);
  EXPECT_EQ(field.image.heightPx(), 24);
  EXPECT_EQ(field.image.row(3)[1], 16);  // UYVY video black
  EXPECT_EQ(warper.counters().blackFields.load(), 1u);
  Field notFromMakeField;
  EXPECT_EQ(warper.produce(Frame{}, Pose{}, FieldSpec{}, notFromMakeField), FieldStatus::BadOutput);
}

TEST(FieldWarper, FieldCarriesItsSpecAndSource) {
  FieldWarperConfig cfg;
  cfg.rasterWidthPx = kW;
  cfg.rasterHeightPx = kH;
  FieldWarper warper(cfg);
  Field field = warper.makeField();
  Frame frame = scene();
  frame.frameNumber = 77;
  frame.poseTime = TimePoint{Nanoseconds{5}};
  const FieldSpec spec{12, TimePoint{Nanoseconds{1234}}, FieldParity::Bottom};
  ASSERT_EQ(warper.produce(frame, frame.pose, spec, field), FieldStatus::Ok);
  EXPECT_EQ(field.fieldNumber, 12u);
  EXPECT_EQ(field.displayTime, spec.displayTime);
  EXPECT_EQ(field.parity, FieldParity::Bottom);
  EXPECT_EQ(field.sourceFrameNumber, 77u);
  EXPECT_EQ(field.sourcePoseTime, frame.poseTime);
  EXPECT_EQ(field.rasterHeightPx, kH);
  EXPECT_EQ(field.marginViolations, 0u);
}

// A frame that comes with its flicker-filtered copy (made by its producer: makeFlickerFiltered)
// is sampled from that copy, and the field is the one the warper makes filtering the frame itself;
// a copy of other pixels shows in the field (it is the copy that is sampled); a copy not marked
// made, or of another shape, is not the frame's, and the warper filters the frame itself.
TEST(FieldWarper, SamplesTheFlickerFilteredCopyTheFrameComesWith) {
  FieldWarperConfig cfg;
  cfg.rasterWidthPx = kW;
  cfg.rasterHeightPx = kH;
  cfg.flickerFilter = true;
  cfg.maxFrameWidthPx = scene().image.widthPx();
  cfg.maxFrameHeightPx = scene().image.heightPx();
  const auto fieldOf = [&](const Frame& frame) {
    FieldWarper warper(cfg);  // a new warper each time: nothing kept from another frame
    Field field = warper.makeField();
    EXPECT_EQ(warper.produce(frame, frame.pose, FieldSpec{0, TimePoint{}, FieldParity::Top}, field), FieldStatus::Ok);
    return field.image;
  };
  const Image filteredHere = fieldOf(scene());
  Frame withCopy = scene();
  ASSERT_TRUE(makeFlickerFiltered(withCopy));
  EXPECT_EQ(fieldOf(withCopy), filteredHere);

  Frame inverted = scene();
  for (std::uint8_t& b : inverted.image.bytes()) b = static_cast<std::uint8_t>(255 - b);
  const Image invertedField = fieldOf(inverted);
  EXPECT_NE(invertedField, filteredHere);
  ASSERT_TRUE(makeFlickerFiltered(inverted));
  Frame foreign = scene();
  foreign.flickerFiltered = inverted.flickerFiltered;
  foreign.hasFlickerFiltered = true;
  EXPECT_EQ(fieldOf(foreign), invertedField);
  foreign.hasFlickerFiltered = false;  // as a recycled frame's: the copy is another picture's
  EXPECT_EQ(fieldOf(foreign), filteredHere);

  Frame wrongShape = scene();
  wrongShape.flickerFiltered = Image(8, 8, wrongShape.image.format());
  wrongShape.hasFlickerFiltered = true;
  EXPECT_EQ(fieldOf(wrongShape), filteredHere);
}

TEST(FieldWarper, AFieldBeyondTheFramesReachShowsThePreviousPictureAgain) {
  FieldWarperConfig cfg;
  cfg.rasterWidthPx = kW;
  cfg.rasterHeightPx = kH;
  const Frame& frame = scene();  // from 150 m up, 15° down: its nearest control point is ~300 m away
  const auto bytes = [](const Field& f) {
    const auto b = f.image.bytes();
    return std::vector<std::uint8_t>(b.begin(), b.end());
  };
  FieldWarper warper(cfg);
  Field field = warper.makeField();
  const FieldSpec spec{0, TimePoint{}, FieldParity::Progressive};
  Pose near = frame.pose;
  near.positionM.x += 40.0;  // motion the warp extrapolates
  ASSERT_EQ(warper.produce(frame, near, spec, field), FieldStatus::Ok);
  const std::vector<std::uint8_t> shown = bytes(field);
  Pose far = frame.pose;
  far.positionM += glm::dvec3{3000.0, -2000.0, 50.0};  // a reposition
  const TimePoint shownAt = frame.poseTime + std::chrono::milliseconds(50);
  EXPECT_TRUE(beyondWarpReach(frame, far, shownAt));
  EXPECT_FALSE(beyondWarpReach(frame, near, shownAt));
  Frame newer = frame;  // the same picture, numbered as a newer frame
  newer.frameNumber = frame.frameNumber + 1;
  EXPECT_EQ(warper.produce(newer, far, FieldSpec{1, shownAt, FieldParity::Progressive}, field), FieldStatus::Held);
  EXPECT_EQ(bytes(field), shown);  // the previous picture, not the old place smeared over the new
  EXPECT_EQ(field.fieldNumber, 1u);
  EXPECT_EQ(field.sourceFrameNumber, frame.frameNumber);  // ... and said to come from where it came from
  EXPECT_EQ(warper.counters().heldFields.load(), 1u);
  EXPECT_EQ(warper.counters().blackFields.load(), 0u);

  // Nothing shown yet: black.
  FieldWarper fresh(cfg);
  Field first = fresh.makeField();
  EXPECT_EQ(fresh.produce(frame, far, FieldSpec{0, shownAt, FieldParity::Progressive}, first), FieldStatus::Held);
  EXPECT_EQ(first.image.row(kH / 2)[1], 16);  // UYVY video black

  // Fast and close to the ground is motion, not a reposition: 4 m from a frame whose nearest
  // surface is 5 m away, 50 ms later (80 m/s), is warped; so is a frame 1 s stale at 250 m/s.
  Frame low = frame;
  low.controlPoints[7].kind = ControlPointKind::Surface;
  low.controlPoints[7].world = frame.pose.positionM + glm::dvec3{0.0, 3.0, -4.0};
  Pose rolled = frame.pose;
  rolled.positionM.y += 4.0;
  EXPECT_FALSE(beyondWarpReach(low, rolled, shownAt));
  EXPECT_TRUE(beyondWarpReach(low, rolled, frame.poseTime));  // the same move at once: a jump
  Pose flown = frame.pose;
  flown.positionM.y += 250.0;
  EXPECT_FALSE(beyondWarpReach(frame, flown, frame.poseTime + std::chrono::seconds(1)));

  // A frame that saw only sky is never out of reach.
  Frame sky = frame;
  for (ControlPoint& cp : sky.controlPoints) cp.kind = ControlPointKind::Sky;
  EXPECT_FALSE(beyondWarpReach(sky, far, frame.poseTime));
}

}  // namespace
}  // namespace fieldcast::warp
