// The AGC's luma sum along an R'G'B' row in SIMD lanes, one pixel per 32-bit lane, compiled for
// every level Highway dispatches to. Each lane computes its pixel's luma as the scalar form does;
// with every other pixel asked for, the odd lanes are left out of the sum. The same sums as
// LumaSum.h's scalar reference.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "LumaSumLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "LumaSum.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace fieldcast::warp::luma::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

std::uint64_t RgbLumaSumRow(const std::uint8_t* HWY_RESTRICT row, int widthPx, bool everyOther) {
  int x = 0;
  std::uint64_t sum = 0;
#if HWY_TARGET != HWY_SCALAR  // every other lane needs two lanes: one lane is the scalar form below
  const hn::ScalableTag<std::int32_t> di;
  const hn::Rebind<std::uint8_t, decltype(di)> d8;
  const int lanes = static_cast<int>(hn::Lanes(di));
  // Lanes summed: all, or the even ones (an even count of lanes keeps x even from block to block)
  const auto counted =
      everyOther ? hn::Eq(hn::And(hn::Iota(di, 0), hn::Set(di, 1)), hn::Zero(di)) : hn::Eq(hn::Zero(di), hn::Zero(di));
  const auto wr = hn::Set(di, kWr), wg = hn::Set(di, kWg), wb = hn::Set(di, kWb);
  auto total = hn::Zero(di);  // at most 255 a lane per block: 2^22 pixels stay within 31 bits
  for (; x + lanes <= widthPx; x += lanes) {
    hn::Vec<decltype(d8)> r, g, b;
    hn::LoadInterleaved3(d8, row + 3 * x, r, g, b);
    const auto weighted = hn::Add(hn::Add(hn::Mul(hn::PromoteTo(di, r), wr), hn::Mul(hn::PromoteTo(di, g), wg)),
                                  hn::Mul(hn::PromoteTo(di, b), wb));
    total = hn::Add(total, hn::IfThenElseZero(counted, hn::ShiftRight<8>(weighted)));
  }
  sum = static_cast<std::uint64_t>(hn::GetLane(hn::SumOfLanes(di, total)));
#endif
  return sum + lumaSumRowScalar(row + 3 * x, 3, widthPx - x, everyOther ? 2 : 1);
}

}  // namespace fieldcast::warp::luma::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fieldcast::warp::luma {

HWY_EXPORT(RgbLumaSumRow);

std::uint64_t rgbLumaSumRowLanes(const std::uint8_t* row, int widthPx, bool everyOther) noexcept {
  return HWY_DYNAMIC_DISPATCH(RgbLumaSumRow)(row, widthPx, everyOther);
}

}  // namespace fieldcast::warp::luma
#endif
