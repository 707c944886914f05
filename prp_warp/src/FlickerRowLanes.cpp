// The flicker filter's row in SIMD lanes: (a + 2b + c + 2) >> 2 as two rounded means of bytes, in
// byte lanes (no widening); compiled for every level Highway dispatches to. The same bytes as
// FlickerRow.h.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "FlickerRowLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "FlickerRow.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace fieldcast::warp::flicker::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void FilterRow(const std::uint8_t* HWY_RESTRICT above, const std::uint8_t* HWY_RESTRICT here,
               const std::uint8_t* HWY_RESTRICT below, int n, std::uint8_t* HWY_RESTRICT out) {
  const hn::ScalableTag<std::uint8_t> d8;
  const int lanes = static_cast<int>(hn::Lanes(d8));
  const auto one = hn::Set(d8, 1);
  int i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto a = hn::LoadU(d8, above + i), b = hn::LoadU(d8, here + i), c = hn::LoadU(d8, below + i);
    // h = floor((a + c) / 2): the rounded-up mean less the bit it rounded up. Then
    // (a + 2b + c + 2) >> 2 = (h + b + 1) >> 1, the rounded-up mean of h and b: with a + c = 2h + l,
    // the l/2 it drops moves (h + b + 1) / 2 by a quarter at most, never past an integer.
    const auto h = hn::Sub(hn::AverageRound(a, c), hn::And(hn::Xor(a, c), one));
    hn::StoreU(hn::AverageRound(h, b), d8, out + i);
  }
  filterRowScalar(above + i, here + i, below + i, n - i, out + i);
}

}  // namespace fieldcast::warp::flicker::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fieldcast::warp::flicker {

HWY_EXPORT(FilterRow);

void filterRowLanes(const std::uint8_t* above, const std::uint8_t* here, const std::uint8_t* below, int n,
                    std::uint8_t* out) noexcept {
  HWY_DYNAMIC_DISPATCH(FilterRow)(above, here, below, n, out);
}

}  // namespace fieldcast::warp::flicker
#endif
