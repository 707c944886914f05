#pragma once
// Random spans between two crossings of a column, as the column-plane march hands them to the
// fill: for SpanFillTest (fast fill against the reference) and the span fill benchmark.
#include "../../src/render/SpanFill.h"

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace fieldcast::core::test {

/// One call of the fill: the span, the far crossing's row and the sub-row (and its centre) to start at.
struct SpanFillCase {
  CrossingSpan span;
  double vStop;
  int q;
  double vq;
};

/// The fill constants of a column at camera-space x `xc`, one sub-row per pixel, for a camera
/// whose principal point is at row `cyPx` and whose focal length is `fyPx` pixels.
inline ColumnFill columnFillFor(const Shading& shading, double xc, double cyPx, double fyPx) {
  return ColumnFill{shading.pixelShader(),
                    1.0f,
                    static_cast<float>(cyPx),
                    static_cast<float>(1.0 / fyPx),
                    static_cast<float>(1.0 + xc * xc),
                    1.0};
}

/// `count` spans in a column of `rows` pixels, each covering 0 to `maxSpanRows` sub-rows (some
/// run past sub-row 0), at depths from 5 m to 8 km, with random crossing colours.
inline std::vector<SpanFillCase> makeSpanFillCases(std::uint32_t seed, int count, int rows, int maxSpanRows) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> row(0, rows - 1), spanRows(0, maxSpanRows), byte(0, 255);
  const auto colour = [&] {
    return unpackRgb(static_cast<std::uint32_t>(byte(rng)) | static_cast<std::uint32_t>(byte(rng)) << 8 |
                     static_cast<std::uint32_t>(byte(rng)) << 16);
  };
  std::vector<SpanFillCase> cases;
  cases.reserve(static_cast<std::size_t>(count));
  for (int n = 0; n < count; ++n) {
    SpanFillCase c{};
    c.q = row(rng);
    // The march's row centre drifts from (q + ½) by its running sum; the near crossing lies within
    // a sub-row below it, the far one a whole number of sub-rows and a fraction above.
    c.vq = c.q + 0.5 + (unit(rng) - 0.5) * 1e-9;
    const double v0 = c.vq + unit(rng);
    c.vStop = c.vq - spanRows(rng) - unit(rng);
    const double depth0 = 5.0 * std::pow(1600.0, unit(rng));
    const double depth1 = depth0 * (1.0 + 0.3 * unit(rng));
    c.span = CrossingSpan{static_cast<float>(v0),
                          static_cast<float>(1.0 / (c.vStop - v0)),
                          static_cast<float>(1.0 / depth0),
                          static_cast<float>(1.0 / depth1),
                          colour(),
                          colour()};
    cases.push_back(c);
  }
  return cases;
}

}  // namespace fieldcast::core::test
