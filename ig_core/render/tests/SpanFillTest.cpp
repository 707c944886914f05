// The four-lane span fill against the one-pixel-at-a-time reference: the same bytes, ranges, last
// sub-row and row centre, for colour and grey, with and without haze, ranges and pixels, on the
// spans the march makes and on spans made to drive every clamp.
#include "SpanFillCases.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace fieldcast::core::test {
namespace {

constexpr int kRows = 584;  // a 720×486 display's frame height with its margins
constexpr std::uint8_t kUnwritten = 0xA5;

struct FillOutput {
  std::vector<std::uint8_t> pixels;
  std::vector<float> ranges;
  int q = 0;
  double vq = 0.0;
};

// With `stick`, the fill of a span on that stick's texels (fillStickSpan and StickSpanPixel).
template <bool kGrey>
FillOutput fill(bool fast, const SpanFillCase& c, const ColumnFill& column, bool withPixels, bool withRanges,
                const StickSpan* stick = nullptr) {
  const std::size_t bpp = kGrey ? 1 : 3;
  FillOutput out;
  out.pixels.assign(kRows * bpp, kUnwritten);
  out.ranges.assign(kRows, -1.0f);
  const ColumnPixels target{withPixels ? out.pixels.data() : nullptr, withRanges ? out.ranges.data() : nullptr, bpp};
  out.q = c.q;
  out.vq = c.vq;
  if (stick != nullptr) {
    if (fast) {
      fillStickSpan<kGrey>(c.span, column, target, c.vStop, out.q, out.vq, *stick);
    } else {
      fillSpanReference<kGrey>(c.span, column, target, c.vStop, out.q, out.vq, StickSpanPixel{*stick});
    }
  } else if (fast) {
    fillSpan<kGrey>(c.span, column, target, c.vStop, out.q, out.vq);
  } else {
    fillSpanReference<kGrey>(c.span, column, target, c.vStop, out.q, out.vq);
  }
  return out;
}

struct Setup {
  double hazeRangeM = 3000.0;
  bool withPixels = true;
  bool withRanges = true;
  int spans = 4000;
  SpanFillShape shape{0, 12, false};
  bool onSticks = false;  ///< each span on a random stick's texels instead of between two colours
};

// A stick of 1 … 40 random texels (a third of them not opaque: without secondary rays they are
// drawn as they are), the span's two crossings anywhere from above its top to below its foot, or
// (one in twenty) at a NaN coordinate, under a random sun.
struct RandomStick {
  std::vector<std::uint32_t> texels;
  StickSpan span;
};
RandomStick randomStick(std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  RandomStick s;
  s.texels.resize(1 + rng() % 40);
  for (std::uint32_t& texel : s.texels)
    texel = static_cast<std::uint32_t>((rng() & 0xFFFFFFu) | (rng() % 3 == 0 ? (rng() & 0xFFu) : 0xFFu) << 24);
  const float length = static_cast<float>(s.texels.size());
  const auto coordinate = [&] { return rng() % 20 == 0 ? std::nanf("") : -3.0f + (length + 6.0f) * unit(rng); };
  s.span = StickSpan{s.texels, coordinate(), coordinate(), 0.5f + 0.7f * unit(rng), nullptr};
  return s;
}

template <bool kGrey>
void expectSameAsReference(const Setup& setup) {
  RenderSettings settings;
  settings.colourMode = kGrey ? FrameColour::Grey : FrameColour::Rgb;
  settings.hazeRangeM = setup.hazeRangeM;
  const Shading shading(settings);
  const ColumnFill column = columnFillFor(shading, -0.37, 292.0, 640.0);
  int filled = 0, pastTop = 0, inLanes = 0;
  std::mt19937 sticks(7);
  for (const SpanFillCase& c : makeSpanFillCases(20261202, setup.spans, kRows, setup.shape)) {
    const RandomStick stick = randomStick(sticks);
    const StickSpan* onStick = setup.onSticks ? &stick.span : nullptr;
    const FillOutput reference = fill<kGrey>(false, c, column, setup.withPixels, setup.withRanges, onStick);
    const FillOutput fast = fill<kGrey>(true, c, column, setup.withPixels, setup.withRanges, onStick);
    const std::string where = "span from sub-row " + std::to_string(c.q) + " to row " + std::to_string(c.vStop);
    ASSERT_EQ(fast.q, reference.q) << where;
    ASSERT_EQ(std::memcmp(&fast.vq, &reference.vq, sizeof(double)), 0) << where;
    ASSERT_EQ(fast.pixels, reference.pixels) << where;
    ASSERT_EQ(std::memcmp(fast.ranges.data(), reference.ranges.data(), kRows * sizeof(float)), 0) << where;
    filled += c.q - reference.q;
    if (reference.q < 0) ++pastTop;
    if (c.q - reference.q > 2) ++inLanes;
  }
  // The cases cover what they claim: many sub-rows filled, most spans long enough for the lanes,
  // and spans that run past sub-row 0.
  EXPECT_GT(filled, setup.spans);
  EXPECT_GT(inLanes, setup.spans / 2);
  EXPECT_GT(pastTop, 5);
}

TEST(SpanFill, ColourWithHazeAndRangesMatchesReference) { expectSameAsReference<false>({}); }
TEST(SpanFill, ColourWithoutHazeMatchesReference) { expectSameAsReference<false>({0.0, true, false}); }
TEST(SpanFill, GreyWithHazeMatchesReference) { expectSameAsReference<true>({}); }
// The luma sum's order shows in a few pixels in a million: many spans, no haze to soften it.
TEST(SpanFill, GreyWithoutHazeMatchesReference) { expectSameAsReference<true>({0.0, true, false, 200000}); }
TEST(SpanFill, RangesOnlyMatchReference) { expectSameAsReference<false>({3000.0, false, true}); }
TEST(SpanFill, GreyRangesOnlyMatchReference) { expectSameAsReference<true>({3000.0, false, true}); }
// Rows past the ends of the span's crossings, crossings in either depth order, colours beyond
// 0..255, and haze so short that most ranges pass the end of its table.
TEST(SpanFill, ClampsMatchReferenceInColour) {
  expectSameAsReference<false>({20.0, true, true, 20000, {0, 12, true}});
  expectSameAsReference<false>({300.0, true, true, 20000, {0, 12, true}});
}
TEST(SpanFill, ClampsMatchReferenceInGrey) {
  expectSameAsReference<true>({20.0, true, true, 20000, {0, 12, true}});
  expectSameAsReference<true>({300.0, true, true, 20000, {0, 12, true}});
}

// A stick's texels, nearest texel by its coordinate's floor and clamped to the stick, lit, hazed.
TEST(SpanFill, OnASticksTexelsMatchesReferenceInColour) {
  expectSameAsReference<false>({.onSticks = true});
  expectSameAsReference<false>({.hazeRangeM = 0.0, .onSticks = true});
  expectSameAsReference<false>({.hazeRangeM = 300.0, .spans = 20000, .shape = {0, 12, true}, .onSticks = true});
}
TEST(SpanFill, OnASticksTexelsMatchesReferenceInGrey) {
  expectSameAsReference<true>({.onSticks = true});
  expectSameAsReference<true>({.hazeRangeM = 20.0, .spans = 20000, .shape = {0, 12, true}, .onSticks = true});
}

}  // namespace
}  // namespace fieldcast::core::test
