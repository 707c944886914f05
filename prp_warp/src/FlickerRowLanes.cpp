// The flicker filter's row in SIMD lanes: bytes widened to 16-bit lanes, (a + 2b + c + 2) >> 2,
// narrowed back; compiled for every level Highway dispatches to. The same bytes as FlickerRow.h.
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
  const hn::ScalableTag<std::uint16_t> d16;
  const hn::Rebind<std::uint8_t, decltype(d16)> d8;
  const int lanes = static_cast<int>(hn::Lanes(d16));
  const auto two = hn::Set(d16, 2);
  int i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto a = hn::PromoteTo(d16, hn::LoadU(d8, above + i));
    const auto b = hn::PromoteTo(d16, hn::LoadU(d8, here + i));
    const auto c = hn::PromoteTo(d16, hn::LoadU(d8, below + i));
    const auto sum = hn::Add(hn::Add(a, c), hn::Add(hn::ShiftLeft<1>(b), two));
    hn::StoreU(hn::DemoteTo(d8, hn::BitCast(hn::RebindToSigned<decltype(d16)>(), hn::ShiftRight<2>(sum))), d8, out + i);
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
