// The four-lane span fill against the one-pixel-at-a-time reference: the same bytes, ranges, last
// sub-row and row centre, for colour and grey, with and without haze, ranges and pixels.
#include "SpanFillCases.h"

#include <gtest/gtest.h>

#include <cstring>
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

template <bool kGrey>
FillOutput fill(bool fast, const SpanFillCase& c, const ColumnFill& column, bool withPixels, bool withRanges) {
  const std::size_t bpp = kGrey ? 1 : 3;
  FillOutput out;
  out.pixels.assign(kRows * bpp, kUnwritten);
  out.ranges.assign(kRows, -1.0f);
  const ColumnPixels target{withPixels ? out.pixels.data() : nullptr, withRanges ? out.ranges.data() : nullptr, bpp};
  out.q = c.q;
  out.vq = c.vq;
  if (fast) {
    fillSpan<kGrey>(c.span, column, target, c.vStop, out.q, out.vq);
  } else {
    fillSpanReference<kGrey>(c.span, column, target, c.vStop, out.q, out.vq);
  }
  return out;
}

template <bool kGrey>
void expectSameAsReference(bool haze, bool withPixels, bool withRanges) {
  RenderSettings settings;
  settings.colourMode = kGrey ? FrameColour::Grey : FrameColour::Rgb;
  settings.hazeRangeM = haze ? 3000.0 : 0.0;
  const Shading shading(settings);
  const ColumnFill column = columnFillFor(shading, -0.37, 292.0, 640.0);
  int filled = 0, pastTop = 0;
  for (const SpanFillCase& c : makeSpanFillCases(20261202, 4000, kRows, 12)) {
    const FillOutput reference = fill<kGrey>(false, c, column, withPixels, withRanges);
    const FillOutput fast = fill<kGrey>(true, c, column, withPixels, withRanges);
    const std::string where = "span from sub-row " + std::to_string(c.q) + " to row " + std::to_string(c.vStop);
    ASSERT_EQ(fast.q, reference.q) << where;
    ASSERT_EQ(std::memcmp(&fast.vq, &reference.vq, sizeof(double)), 0) << where;
    ASSERT_EQ(fast.pixels, reference.pixels) << where;
    ASSERT_EQ(std::memcmp(fast.ranges.data(), reference.ranges.data(), kRows * sizeof(float)), 0) << where;
    filled += c.q - reference.q;
    if (reference.q < 0) ++pastTop;
  }
  // The cases cover what they claim: many sub-rows filled, and spans that run past sub-row 0.
  EXPECT_GT(filled, 10000);
  EXPECT_GT(pastTop, 5);
}

TEST(SpanFill, ColourWithHazeAndRangesMatchesReference) { expectSameAsReference<false>(true, true, true); }
TEST(SpanFill, ColourWithoutHazeMatchesReference) { expectSameAsReference<false>(false, true, false); }
TEST(SpanFill, GreyWithHazeMatchesReference) { expectSameAsReference<true>(true, true, true); }
TEST(SpanFill, RangesOnlyMatchReference) { expectSameAsReference<false>(true, false, true); }

}  // namespace
}  // namespace fieldcast::core::test
