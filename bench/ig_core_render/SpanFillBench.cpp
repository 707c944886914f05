// The column-plane march's per-pixel fill: the four-lane fillSpan against the one-pixel-at-a-time
// reference, on random spans of 1–2, 3–4 (as looking down at the built-in terrain from 400 m, where
// 89% of spans are 3 or 4 sub-rows), 1–4 and 1–12 sub-rows (at low pitch 70% are one). Colour with
// haze, as the service renders it; and the same spans on a stick's side (fillStickSpan: sixteen
// opaque texels, the far crossing nine texels below the near one). Arguments: fewest and most
// sub-rows a span covers. Counter px_per_s: sub-rows filled per second.
//
//   fieldcast_bench_span_fill [benchmark flags]
#include "SpanFillCases.h"

#include <benchmark/benchmark.h>

#include <vector>

namespace fieldcast::core::test {
namespace {

constexpr int kRows = 584;

template <bool kFast, bool kStick>
void BM_SpanFill(benchmark::State& state) {
  RenderSettings settings;
  const Shading shading(settings);
  const ColumnFill column = columnFillFor(shading, -0.37, 292.0, 640.0);
  const std::vector<SpanFillCase> cases =
      makeSpanFillCases(7, 4096, kRows, {static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), false});
  std::vector<std::uint32_t> texels(16);
  for (std::size_t k = 0; k < texels.size(); ++k) texels[k] = 0xFF000000u | static_cast<std::uint32_t>(k * 0x0F0B07u);
  const StickSpan stick{texels, 3.0f, 12.0f, 1.0f, nullptr};
  std::vector<std::uint8_t> pixels(kRows * 3);
  const ColumnPixels target{pixels.data(), nullptr, 3};
  std::int64_t filled = 0;
  for (auto _ : state) {
    for (const SpanFillCase& c : cases) {
      int q = c.q;
      double vq = c.vq;
      if (kFast && kStick) {
        fillStickSpan<false>(c.span, column, target, c.vStop, q, vq, stick);
      } else if (kStick) {
        fillSpanReference<false>(c.span, column, target, c.vStop, q, vq, StickSpanPixel{stick});
      } else if (kFast) {
        fillSpan<false>(c.span, column, target, c.vStop, q, vq);
      } else {
        fillSpanReference<false>(c.span, column, target, c.vStop, q, vq);
      }
      filled += c.q - q;
    }
    benchmark::DoNotOptimize(pixels.data());
    benchmark::ClobberMemory();
  }
  state.counters["px_per_s"] = benchmark::Counter(static_cast<double>(filled), benchmark::Counter::kIsRate);
}

BENCHMARK_TEMPLATE(BM_SpanFill, false, false)
    ->Name("SpanFillReference")
    ->Args({1, 2})
    ->Args({3, 4})
    ->Args({1, 4})
    ->Args({1, 12});
BENCHMARK_TEMPLATE(BM_SpanFill, true, false)->Name("SpanFill")->Args({1, 2})->Args({3, 4})->Args({1, 4})->Args({1, 12});
BENCHMARK_TEMPLATE(BM_SpanFill, false, true)->Name("StickSpanFillReference")->Args({1, 2})->Args({3, 4})->Args({1, 12});
BENCHMARK_TEMPLATE(BM_SpanFill, true, true)->Name("StickSpanFill")->Args({1, 2})->Args({3, 4})->Args({1, 12});

}  // namespace
}  // namespace fieldcast::core::test

BENCHMARK_MAIN();
