// Field post-processing: BT.601 conversion, AGC smoothing, flicker filter.
#include <prp_warp/PostProcess.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace fieldcast::warp {
namespace {

Image rgbPair(std::array<std::uint8_t, 3> a, std::array<std::uint8_t, 3> b) {
  Image img(2, 1, PixelFormat::Rgb8);
  std::copy(a.begin(), a.end(), img.row(0));
  std::copy(b.begin(), b.end(), img.row(0) + 3);
  return img;
}

TEST(ConvertPixels, Bt601VideoRangeUyvyOfReferenceColours) {
  Image out(2, 1, PixelFormat::Uyvy422);
  struct Case {
    std::array<std::uint8_t, 3> rgb;
    int y, cb, cr;
  };
  // ITU-R BT.601 75 %/100 % colour bar values for 100 % primaries
  const Case cases[] = {{{255, 255, 255}, 235, 128, 128}, {{0, 0, 0}, 16, 128, 128},   {{255, 0, 0}, 81, 90, 240},
                        {{0, 255, 0}, 145, 54, 34},       {{0, 0, 255}, 41, 240, 110}, {{255, 255, 0}, 210, 16, 146}};
  for (const Case& c : cases) {
    ASSERT_TRUE(convertPixels(rgbPair(c.rgb, c.rgb), out));
    const std::uint8_t* p = out.row(0);
    EXPECT_NEAR(p[0], c.cb, 1) << int(c.rgb[0]) << "," << int(c.rgb[1]) << "," << int(c.rgb[2]);
    EXPECT_NEAR(p[1], c.y, 1);
    EXPECT_NEAR(p[2], c.cr, 1);
    EXPECT_NEAR(p[3], c.y, 1);
  }
  // Chroma of a pair is the mean of both pixels; luma stays per pixel
  ASSERT_TRUE(convertPixels(rgbPair({255, 255, 255}, {0, 0, 0}), out));
  EXPECT_EQ(out.row(0)[1], 235);
  EXPECT_EQ(out.row(0)[3], 16);
  EXPECT_EQ(out.row(0)[0], 128);
}

TEST(ConvertPixels, UyvyStaysInVideoRangeForEveryExtremeColour) {
  Image out(2, 1, PixelFormat::Uyvy422);
  for (int c = 0; c < 64; ++c) {
    const auto level = [&](int bit) { return static_cast<std::uint8_t>((c >> bit) & 1 ? 255 : 0); };
    ASSERT_TRUE(convertPixels(rgbPair({level(0), level(1), level(2)}, {level(3), level(4), level(5)}), out));
    const std::uint8_t* p = out.row(0);
    for (int i : {1, 3}) EXPECT_TRUE(p[i] >= 16 && p[i] <= 235) << c;
    for (int i : {0, 2}) EXPECT_TRUE(p[i] >= 16 && p[i] <= 240) << c;
  }
}

TEST(ConvertPixels, GreyAndRgbConversions) {
  Image grey(2, 1, PixelFormat::Grey8);
  ASSERT_TRUE(convertPixels(rgbPair({255, 0, 0}, {10, 200, 30}), grey));
  EXPECT_EQ(grey.row(0)[0], 77);  // 0.299 · 255
  EXPECT_NEAR(grey.row(0)[1], 0.299 * 10 + 0.587 * 200 + 0.114 * 30, 1.0);
  Image rgb(2, 1, PixelFormat::Rgb8);
  ASSERT_TRUE(convertPixels(grey, rgb));
  EXPECT_EQ(rgb.row(0)[0], 77);
  EXPECT_EQ(rgb.row(0)[2], 77);
  Image uyvy(2, 1, PixelFormat::Uyvy422);
  grey.row(0)[0] = 255;
  grey.row(0)[1] = 0;
  ASSERT_TRUE(convertPixels(grey, uyvy));
  EXPECT_EQ(uyvy.row(0)[1], 235);
  EXPECT_EQ(uyvy.row(0)[3], 16);
}

TEST(ConvertPixels, RejectsMismatchedSizes) {
  const Image grey(4, 2, PixelFormat::Grey8);
  Image smaller(2, 2, PixelFormat::Grey8);
  EXPECT_FALSE(convertPixels(grey, smaller));
}

TEST(FillBlack, IsVideoBlackInUyvy) {
  Image uyvy(4, 2, PixelFormat::Uyvy422);
  fillBlack(uyvy);
  EXPECT_EQ(uyvy.row(1)[0], 128);
  EXPECT_EQ(uyvy.row(1)[1], 16);
}

TEST(AutoGain, ConvergesToTheTargetWithTheConfiguredTimeConstant) {
  AutoGainConfig cfg;
  cfg.enabled = true;
  cfg.targetMeanLevel = 120.0;
  cfg.timeConstantS = 0.5;
  AutoGain agc(cfg);
  const Nanoseconds field{16'683'333};
  // A dark scene (mean 40): the wanted gain is 3
  Image img(64, 32, PixelFormat::Grey8);
  std::fill(img.bytes().begin(), img.bytes().end(), std::uint8_t{40});
  Image work = img;
  agc.process(work, field);
  // One field moves the gain by 1 − e^(−T/τ) of the way only: no pumping
  EXPECT_NEAR(agc.gain(), 1.0 + 2.0 * (1.0 - std::exp(-0.016683333 / 0.5)), 1e-6);
  for (int i = 0; i < 600; ++i) {  // ten seconds
    work = img;
    agc.process(work, field);
  }
  EXPECT_NEAR(agc.gain(), 3.0, 1e-3);
  EXPECT_EQ(work.row(0)[0], 120);
  // Limited to maxGain for a black scene
  std::fill(img.bytes().begin(), img.bytes().end(), std::uint8_t{0});
  for (int i = 0; i < 600; ++i) {
    work = img;
    agc.process(work, field);
  }
  EXPECT_NEAR(agc.gain(), cfg.maxGain, 1e-3);
}

TEST(AutoGain, DisabledLeavesTheImageAlone) {
  AutoGain agc;
  Image img(8, 8, PixelFormat::Rgb8);
  std::fill(img.bytes().begin(), img.bytes().end(), std::uint8_t{33});
  const Image before = img;
  agc.process(img, Nanoseconds{16'000'000});
  EXPECT_EQ(img, before);
}

TEST(FlickerFilter, SmoothsOneLineDetailVertically) {
  Image lines(4, 6, PixelFormat::Grey8);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 4; ++x) lines.row(y)[x] = y == 2 ? 200 : 0;
  Image out(4, 6, PixelFormat::Grey8);
  ASSERT_TRUE(flickerFilter(lines, out));
  EXPECT_EQ(out.row(1)[0], 50);
  EXPECT_EQ(out.row(2)[0], 100);
  EXPECT_EQ(out.row(3)[0], 50);
  EXPECT_EQ(out.row(4)[0], 0);
  // A flat image is unchanged, edges included
  Image flat(4, 6, PixelFormat::Rgb8);
  std::fill(flat.bytes().begin(), flat.bytes().end(), std::uint8_t{77});
  Image flatOut(4, 6, PixelFormat::Rgb8);
  ASSERT_TRUE(flickerFilter(flat, flatOut));
  EXPECT_EQ(flatOut, flat);
  EXPECT_FALSE(flickerFilter(flat, out));  // format mismatch
}

// The producer's copy (makeFlickerFiltered) has the frame's shape and the filter's bytes, each
// time from the frame's own image (a smaller frame after a larger one, and another picture of
// the same shape, whose copy is not resized); a UYVY frame cannot
// be filtered and gets none.
TEST(FlickerFilter, AFramesCopyIsItsImageFiltered) {
  Frame frame;
  for (const auto [w, h, seed] : {std::tuple{40, 30, 1u}, std::tuple{24, 18, 2u}, std::tuple{24, 18, 3u}}) {
    frame.image = Image(w, h, PixelFormat::Rgb8);
    std::uint32_t state = seed;
    for (std::uint8_t& b : frame.image.bytes())
      b = static_cast<std::uint8_t>((state = state * 1664525u + 1013904223u) >> 24);
    ASSERT_TRUE(makeFlickerFiltered(frame));
    EXPECT_TRUE(frame.hasFlickerFiltered);
    Image expected(w, h, PixelFormat::Rgb8);
    ASSERT_TRUE(flickerFilterReference(frame.image, expected));
    EXPECT_EQ(frame.flickerFiltered, expected);
    EXPECT_NE(frame.flickerFiltered, frame.image);
  }
  frame.image = Image(8, 4, PixelFormat::Uyvy422);
  EXPECT_FALSE(makeFlickerFiltered(frame));
  EXPECT_FALSE(frame.hasFlickerFiltered);
}

}  // namespace
}  // namespace fieldcast::warp
