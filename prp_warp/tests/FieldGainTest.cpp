// The automatic gain in the field warper: the gain measured on a field is applied to that same
// field as it is converted to the output format.
#include "AnalyticScene.h"

#include <prp_warp/FieldWarper.h>
#include <prp_warp/PostProcess.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace fieldcast::warp {
namespace {

constexpr int kW = 160, kH = 120;  // test::obliqueFrame()'s display window

Image fieldOf(PixelFormat format, const AutoGainConfig& gain) {
  FieldWarperConfig cfg;
  cfg.rasterWidthPx = kW;
  cfg.rasterHeightPx = kH;
  cfg.outputFormat = format;
  cfg.autoGain = gain;
  FieldWarper warper(cfg);
  Field field = warper.makeField();
  const Frame& scene = test::obliqueFrame();
  EXPECT_EQ(warper.produce(scene, scene.pose, FieldSpec{0, TimePoint{}, FieldParity::Bottom}, field), FieldStatus::Ok);
  return field.image;
}

TEST(FieldGain, TheGainMeasuredOnAFieldBrightensThatField) {
  const Image plain = fieldOf(PixelFormat::Rgb8, AutoGainConfig{});
  // A gain that settles at once (no time constant), steering to 1.6 × the field's mean
  AutoGainConfig agc;
  agc.enabled = true;
  agc.timeConstantS = 0.0;
  agc.targetMeanLevel = 1.6 * meanLuma(plain, 2);
  const auto gainQ16 = static_cast<std::int32_t>(std::lround(1.6 * 65536.0));
  ASSERT_LT(agc.targetMeanLevel, 255.0);

  const Image gained = fieldOf(PixelFormat::Rgb8, agc);
  int brighter = 0;
  for (std::size_t i = 0; i < plain.bytes().size(); ++i) {
    const int expected = std::min((plain.bytes()[i] * gainQ16 + (1 << 15)) >> 16, 255);
    ASSERT_EQ(gained.bytes()[i], expected) << "byte " << i;
    brighter += gained.bytes()[i] > plain.bytes()[i];
  }
  EXPECT_GT(brighter, static_cast<int>(plain.bytes().size()) / 2);

  // In UYVY the gain is applied before the conversion, as to the RGB field
  Image expected(kW, plain.heightPx(), PixelFormat::Uyvy422);
  ASSERT_TRUE(convertPixelsReference(gained, expected));
  const Image uyvy = fieldOf(PixelFormat::Uyvy422, agc);
  EXPECT_EQ(uyvy, expected);
}

}  // namespace
}  // namespace fieldcast::warp
