// The field written once: FieldWarper's fields, each warped piece mirrored, measured and converted
// as the warp writes it, are byte for byte the field warped whole, mirrored in place and converted
// by the reference conversion under the gain measured on the field before.
#include "AnalyticScene.h"

#include <prp_warp/FieldWarper.h>
#include <prp_warp/PostProcess.h>
#include <prp_warp/Warp.h>

#include <gtest/gtest.h>

#include <string>

namespace fieldcast::warp {
namespace {

// test::obliqueFrame() in grey (its range image kept)
const Frame& greyScene() {
  static const Frame frame = [] {
    Frame f = test::obliqueFrame();
    Image grey(f.image.widthPx(), f.image.heightPx(), PixelFormat::Grey8);
    convertPixelsReference(f.image, grey);
    f.image = grey;
    return f;
  }();
  return frame;
}

// What FieldWarper::produce did before its fields were written once: the warp into an image of the
// frame's format, then the mirror in place, then the conversion (the gain measured afterwards)
Image wholeThenConverted(Warp& warp, const Frame& frame, const Pose& pose, FieldParity parity, Mirror mirror,
                         PixelFormat outFormat, std::int32_t gainQ16, Image& warped) {
  const int rows = fieldRowCount(parity, warp.rasterHeightPx());
  FieldParity sampled = parity;
  if (mirrorsRows(mirror) && parity != FieldParity::Progressive && warp.rasterHeightPx() % 2 == 0) {
    sampled = parity == FieldParity::Top ? FieldParity::Bottom : FieldParity::Top;
  }
  warped = Image(warp.rasterWidthPx(), rows, frame.image.format());
  EXPECT_EQ(warp.warp(frame, pose, sampled, warped).status, WarpStatus::Ok);
  mirrorInPlace(warped, mirror);
  Image out(warp.rasterWidthPx(), rows, outFormat);
  EXPECT_TRUE(convertPixelsReference(warped, out, gainQ16));
  return out;
}

struct Case {
  WarpKind warp;
  PixelFormat frameFormat;
  PixelFormat outFormat;
};

class FieldWrittenOnce : public ::testing::TestWithParam<Case> {};

TEST_P(FieldWrittenOnce, IsTheFieldWarpedWholeMirroredAndConverted) {
  const Case c = GetParam();
  const Frame& frame = c.frameFormat == PixelFormat::Rgb8 ? test::obliqueFrame() : greyScene();
  // Wider than one 256-pixel strip; odd where the format allows, so a mirrored strip starts on an
  // odd column; even raster lines, so a mirror swaps the parity sampled
  const int width =
      c.outFormat == PixelFormat::Uyvy422 ? 2 * frame.displayWidthPx() + 2 : 2 * frame.displayWidthPx() + 1;
  const int height = 2 * frame.displayHeightPx();
  AutoGainConfig agcConfig;
  agcConfig.enabled = true;
  agcConfig.timeConstantS = 0.05;  // moves by a good part of the way each field
  agcConfig.targetMeanLevel = 150.0;

  for (Mirror mirror : {Mirror::None, Mirror::Horizontal, Mirror::Vertical, Mirror::Both}) {
    FieldWarperConfig cfg;
    cfg.warp = c.warp;
    cfg.rasterWidthPx = width;
    cfg.rasterHeightPx = height;
    cfg.outputFormat = c.outFormat;
    cfg.autoGain = agcConfig;
    cfg.mirror = mirror;
    FieldWarper warper(cfg);
    Field field = warper.makeField();
    const std::unique_ptr<Warp> warp = makeWarp(c.warp, width, height);
    AutoGain gain(agcConfig);

    Pose pose = frame.pose;
    bool gainedFieldCompared = false;
    for (int k = 0; k < 4; ++k) {
      const FieldParity parity = k == 3 ? FieldParity::Progressive : k % 2 ? FieldParity::Bottom : FieldParity::Top;
      const FieldSpec spec{static_cast<std::uint64_t>(k), TimePoint{Nanoseconds{k * 16'683'333}}, parity};
      pose.positionM.y += 0.5;
      pose.rollRad += 0.01;
      ASSERT_EQ(warper.produce(frame, pose, spec, field), FieldStatus::Ok);
      Image warped;
      const Image expected =
          wholeThenConverted(*warp, frame, pose, parity, mirror, c.outFormat, gain.gainQ16(), warped);
      const std::string what = std::string(toString(c.warp)) + ", mirror " + std::to_string(static_cast<int>(mirror)) +
                               ", field " + std::to_string(k);
      ASSERT_EQ(field.image, expected) << what;
      EXPECT_EQ(warper.gain(), gain.gainQ16() / 65536.0) << what;  // the gain it says it applied
      gainedFieldCompared = gainedFieldCompared || gain.gainQ16() != 1 << 16;
      gain.update(warped, k == 0 ? Nanoseconds{0} : Nanoseconds{16'683'333});
    }
    // Fields compared under a gain that had moved from unity
    EXPECT_TRUE(gainedFieldCompared);
  }
}

INSTANTIATE_TEST_SUITE_P(KindsAndFormats, FieldWrittenOnce,
                         ::testing::Values(Case{WarpKind::Quadratic, PixelFormat::Rgb8, PixelFormat::Uyvy422},
                                           Case{WarpKind::Quadratic, PixelFormat::Rgb8, PixelFormat::Rgb8},
                                           Case{WarpKind::Quadratic, PixelFormat::Rgb8, PixelFormat::Grey8},
                                           Case{WarpKind::Quadratic, PixelFormat::Grey8, PixelFormat::Grey8},
                                           Case{WarpKind::Quadratic, PixelFormat::Grey8, PixelFormat::Uyvy422},
                                           Case{WarpKind::Hold, PixelFormat::Rgb8, PixelFormat::Uyvy422},
                                           Case{WarpKind::Homography, PixelFormat::Rgb8, PixelFormat::Uyvy422},
                                           Case{WarpKind::Rotation, PixelFormat::Grey8, PixelFormat::Rgb8},
                                           Case{WarpKind::Mesh, PixelFormat::Rgb8, PixelFormat::Uyvy422},
                                           Case{WarpKind::Range3d, PixelFormat::Rgb8, PixelFormat::Rgb8}),
                         [](const auto& p) {
                           return std::string(toString(p.param.warp)) + "_" +
                                  std::string(toString(p.param.frameFormat)) + "_to_" +
                                  std::string(toString(p.param.outFormat));
                         });

}  // namespace
}  // namespace fieldcast::warp
