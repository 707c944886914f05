// The automatic gain in the field warper: the gain measured on a field is applied to the next
// field as it is converted to the output format (one field's lag: each piece of a field is
// converted as the warp writes it).
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

FieldWarperConfig configOf(PixelFormat format, const AutoGainConfig& gain) {
  FieldWarperConfig cfg;
  cfg.rasterWidthPx = kW;
  cfg.rasterHeightPx = kH;
  cfg.outputFormat = format;
  cfg.autoGain = gain;
  return cfg;
}

// The bottom field of the scene at its own pose, from a warper that has made `before` fields
Image fieldOf(FieldWarper& warper, int before = 0) {
  Field field = warper.makeField();
  const Frame& scene = test::obliqueFrame();
  for (int k = 0; k <= before; ++k) {
    const FieldSpec spec{static_cast<std::uint64_t>(k), TimePoint{Nanoseconds{k * 16'683'333}}, FieldParity::Bottom};
    EXPECT_EQ(warper.produce(scene, scene.pose, spec, field), FieldStatus::Ok);
  }
  return field.image;
}

TEST(FieldGain, TheGainMeasuredOnAFieldBrightensTheNext) {
  FieldWarper plainWarper(configOf(PixelFormat::Rgb8, AutoGainConfig{}));
  const Image plain = fieldOf(plainWarper);
  // A gain that settles at once (no time constant), steering to 1.6 × the field's mean
  AutoGainConfig agc;
  agc.enabled = true;
  agc.timeConstantS = 0.0;
  agc.targetMeanLevel = 1.6 * meanLuma(plain, 2);
  const auto gainQ16 = static_cast<std::int32_t>(std::lround(1.6 * 65536.0));
  ASSERT_LT(agc.targetMeanLevel, 255.0);

  // The first field is converted before anything was measured: at unity gain
  FieldWarper warper(configOf(PixelFormat::Rgb8, agc));
  EXPECT_EQ(fieldOf(warper), plain);
  EXPECT_EQ(warper.gain(), 1.0);
  // The second field takes the gain measured on the first (1.6, as applied in 1/65536 steps, only
  // if the warper's mean, summed as the field is written, is meanLuma's)
  const Image gained = fieldOf(warper);
  EXPECT_EQ(warper.gain(), gainQ16 / 65536.0);
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
  FieldWarper uyvyWarper(configOf(PixelFormat::Uyvy422, agc));
  EXPECT_EQ(fieldOf(uyvyWarper, 1), expected);
}

}  // namespace
}  // namespace fieldcast::warp
