#pragma once
// Random spans between two crossings of a column, as the column-plane march hands them to the
// fill: for SpanFillTest (fast fill against the reference) and the span fill benchmark.
#include "SpanFill.h"

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

/// What the spans look like.
struct SpanFillShape {
  int minRows = 1;  ///< sub-rows a span covers from its start (fewer where it runs past sub-row 0)
  int maxRows = 4;
  /// Spans the march does not make, to drive every clamp: the near crossing's row above the
  /// start, the far crossing's row off the stop row, the far crossing nearer than the near one,
  /// and colours outside 0..255.
  bool wild = false;
};

/// `count` spans in a column of `rows` pixels at depths from 5 m to 8 km, with random crossing
/// colours.
inline std::vector<SpanFillCase> makeSpanFillCases(std::uint32_t seed, int count, int rows, SpanFillShape shape) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> row(0, rows - 1), spanRows(shape.minRows, shape.maxRows), byte(0, 255);
  const auto colour = [&] {
    if (shape.wild) {
      const auto channel = [&] { return static_cast<float>(-40.0 + 340.0 * unit(rng)); };
      return Rgb(channel(), channel(), channel());
    }
    return unpackRgb(static_cast<std::uint32_t>(byte(rng)) | static_cast<std::uint32_t>(byte(rng)) << 8 |
                     static_cast<std::uint32_t>(byte(rng)) << 16);
  };
  std::vector<SpanFillCase> cases;
  cases.reserve(static_cast<std::size_t>(count));
  for (int n = 0; n < count; ++n) {
    SpanFillCase c{};
    c.q = row(rng);
    // With one sub-row per pixel the march's row centre is exactly q + ½. The near crossing lies
    // within a sub-row below it; the stop row leaves `covered` centres below it.
    c.vq = c.q + 0.5;
    const int covered = spanRows(rng);
    c.vStop = c.vq - covered + unit(rng);
    double v0 = c.vq + unit(rng);
    double v1 = c.vStop;
    double depth0 = 5.0 * std::pow(1600.0, unit(rng));
    double depth1 = depth0 * (1.0 + 0.3 * unit(rng));
    if (shape.wild) {
      v0 += 2.0 * unit(rng) - 1.5;
      v1 += 2.0 * unit(rng) - 1.0;
      if (unit(rng) < 0.5) std::swap(depth0, depth1);
    }
    c.span = CrossingSpan{static_cast<float>(v0),
                          static_cast<float>(1.0 / (v1 - v0)),
                          static_cast<float>(1.0 / depth0),
                          static_cast<float>(1.0 / depth1),
                          colour(),
                          colour()};
    cases.push_back(c);
  }
  return cases;
}

}  // namespace fieldcast::core::test
