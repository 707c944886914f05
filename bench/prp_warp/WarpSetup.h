#pragma once
// The warp benchmarks' cases, shared by fieldcast_bench_warp and fieldcast_bench_table: the frame
// and field pose of each raster, the service's per-field step, and cv::remap doing the same warp.
// The frame is the analytic ground-plane scene (10 % margins, RGB8, and the same in grey) rendered
// once; the field pose is 80 ms later with 3° of roll, the kind of map the PRP fits every field.
#include "AnalyticScene.h"

#include <motion/PosePredictor.h>
#include <prp_warp/FieldWarper.h>
#include <prp_warp/WarpFit.h>

#include <fieldcast/SimdLevel.h>

#include <opencv2/imgproc.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>

namespace fieldcast::warp {

struct Setup {
  Frame frame;
  Frame greyFrame;  ///< the same view rendered in grey (Grey8)
  Pose fieldPose;
  int rasterW = 0, rasterH = 0;
  QuadraticMap map;
};

/// Raster sizes by number: 0 = NTSC 720 × 486, 1 = 1080i 1920 × 1080; the field's roll (a banked
/// view: the map turns the frame by it). Made once each.
inline const Setup& setup(int which, double rollDeg = 3.0) {
  static std::map<std::pair<int, double>, std::unique_ptr<Setup>> cache;
  auto& s = cache[{which, rollDeg}];
  if (!s) {
    s = std::make_unique<Setup>();
    s->rasterW = which == 0 ? 720 : 1920;
    s->rasterH = which == 0 ? 486 : 1080;
    const Pose framePose{{0.0, 0.0, 300.0}, radians(20.0), radians(-15.0), 0.0};
    s->frame = test::renderFrame(framePose, s->rasterW, s->rasterH, MarginPx{s->rasterW / 10, s->rasterH / 10},
                                 radians(60.0), PixelFormat::Rgb8, 1, true);
    s->greyFrame = test::renderFrame(framePose, s->rasterW, s->rasterH, MarginPx{s->rasterW / 10, s->rasterH / 10},
                                     radians(60.0), PixelFormat::Grey8, 1, true);
    s->fieldPose = framePose;
    s->fieldPose.positionM += glm::dvec3{3.0, 8.0, 1.0};  // 80 ms at ~100 m/s
    s->fieldPose.headingRad += radians(1.0);
    s->fieldPose.rollRad = radians(rollDeg);
    const QuadraticFit fit =
        fitFieldQuadratic(s->frame, s->fieldPose, OutputGeometry::of(s->frame, s->rasterW, s->rasterH));
    s->map = fit.quadratic;
  }
  return *s;
}

/// Runs at one SIMD level while it lives, then puts the best level back.
struct AtLevel {
  explicit AtLevel(const std::string& level) { forceSimdLevel(level); }
  ~AtLevel() { forceSimdLevel("auto"); }
  AtLevel(const AtLevel&) = delete;
  AtLevel& operator=(const AtLevel&) = delete;
};

/// The whole per-field step of the service: pose, fit, warp, AGC, the flicker-filtered frame
/// sampled, conversion to UYVY (or, `grey`, from the grey frame to grey fields); with `newFrames` a
/// new frame every field (a render rate at the field rate: two frames alternate, so each field
/// samples a copy the field before did not read), else every field from the same frame. The
/// frames come with their flicker-filtered copies, as the service's render loop hands them over
/// (makeFlickerFiltered: its cost is the producer's, BM_FlickerFilterFrame).
class FieldStep {
 public:
  FieldStep(const Setup& s, bool newFrames, bool grey = false)
      : mFrames{grey ? s.greyFrame : s.frame, grey ? s.greyFrame : s.frame},
        mNewFrames(newFrames),
        mWarper(config(s, grey)),
        mField(mWarper.makeField()) {
    mFrames[1].frameNumber = mFrames[0].frameNumber + 1;
    for (Frame& f : mFrames) makeFlickerFiltered(f);
    mPoses.push(TimePoint{}, s.frame.pose);  // the field loop's pose source: its cost stays in the figure
    mPoses.push(TimePoint{Nanoseconds{80'000'000}}, s.fieldPose);
  }

  /// Produces the next field.
  FieldStatus run() {
    const FieldSpec spec{mK, TimePoint{Nanoseconds{80'000'000}}, mK % 2 ? FieldParity::Top : FieldParity::Bottom};
    const Frame& frame = mFrames[mNewFrames ? mK % 2 : 0];
    ++mK;
    return mWarper.produce(frame, mPoses.poseAt(spec.displayTime), spec, mField);
  }

 private:
  static FieldWarperConfig config(const Setup& s, bool grey) {
    FieldWarperConfig cfg;
    if (grey) cfg.outputFormat = PixelFormat::Grey8;
    cfg.rasterWidthPx = s.rasterW;
    cfg.rasterHeightPx = s.rasterH;
    cfg.maxFrameWidthPx = s.frame.image.widthPx();
    cfg.maxFrameHeightPx = s.frame.image.heightPx();
    cfg.autoGain.enabled = true;
    cfg.flickerFilter = true;
    return cfg;
  }

  Frame mFrames[2];
  bool mNewFrames;
  FieldWarper mWarper;
  Field mField;
  motion::ConstantVelocityPredictor mPoses;
  std::uint64_t mK = 0;
};

/// OpenCV's remap doing the field's warp, as a user of OpenCV would: the quadratic evaluated into
/// float maps (pixel-centre origin), then cv::remap bilinear with edge replicate, RGB8.
class RemapPerField {
 public:
  explicit RemapPerField(const Setup& s)
      : mS(s),
        mRows(fieldRowCount(FieldParity::Bottom, s.rasterH)),
        mOut(s.rasterW, mRows, PixelFormat::Rgb8),
        mSrc(s.frame.image.heightPx(), s.frame.image.widthPx(), CV_8UC3,
             const_cast<std::uint8_t*>(s.frame.image.row(0))),
        mDst(mRows, s.rasterW, CV_8UC3, mOut.row(0)),
        mMapX(mRows, s.rasterW, CV_32FC1),
        mMapY(mRows, s.rasterW, CV_32FC1) {}

  /// One field: the maps built first when `buildMaps` (as every field needs), then the remap.
  void run(bool buildMaps) {
    if (buildMaps) {
      for (int r = 0; r < mRows; ++r) {
        float* mx = mMapX.ptr<float>(r);
        float* my = mMapY.ptr<float>(r);
        const double v = rasterRow(FieldParity::Bottom, r) + 0.5;
        for (int i = 0; i < mS.rasterW; ++i) {
          const glm::dvec2 p = mS.map({i + 0.5, v});
          mx[i] = static_cast<float>(p.x - 0.5);
          my[i] = static_cast<float>(p.y - 0.5);
        }
      }
    }
    cv::remap(mSrc, mDst, mMapX, mMapY, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  }

 private:
  const Setup& mS;
  int mRows;
  Image mOut;
  cv::Mat mSrc, mDst, mMapX, mMapY;
};

}  // namespace fieldcast::warp
