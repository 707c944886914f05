// The AGC's luma sum along an R'G'B' row in SIMD lanes, one pixel per 16-bit lane, compiled for
// every level Highway dispatches to. Each lane computes its pixel's luma as the scalar form does;
// pairs of lanes are summed into 32 bits by one multiply-add, with the weights (1, 0) when every
// other pixel is asked for. The same sums as LumaSum.h's scalar reference.
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
#if HWY_TARGET != HWY_SCALAR  // pairs of lanes: one lane is the scalar form below
  const hn::ScalableTag<std::uint16_t> d16;
  const hn::Rebind<std::uint8_t, decltype(d16)> d8;
  const hn::RepartitionToWide<hn::RebindToSigned<decltype(d16)>> d32;
  const int lanes = static_cast<int>(hn::Lanes(d16));
  const auto wr = hn::Set(d16, kWr), wg = hn::Set(d16, kWg), wb = hn::Set(d16, kWb);
  // Each pair of lanes summed with these weights: (1, 0) keeps the even pixel, (1, 1) both
  const auto weights = hn::BitCast(hn::RebindToSigned<decltype(d16)>(), hn::Set(d32, everyOther ? 1 : 0x10001));
  auto even = hn::Zero(d32), odd = hn::Zero(d32);  // 2 · 255 a lane per block: 2^22 pixels fit 31 bits
  for (; x + lanes <= widthPx; x += lanes) {
    hn::Vec<decltype(d8)> r, g, b;
    hn::LoadInterleaved3(d8, row + 3 * x, r, g, b);
    // At most 256 · 255: the weighted sum fits 16 bits, the luma 8
    const auto weighted = hn::Add(hn::Add(hn::Mul(hn::PromoteTo(d16, r), wr), hn::Mul(hn::PromoteTo(d16, g), wg)),
                                  hn::Mul(hn::PromoteTo(d16, b), wb));
    const auto luma = hn::BitCast(hn::RebindToSigned<decltype(d16)>(), hn::ShiftRight<8>(weighted));
    even = hn::ReorderWidenMulAccumulate(d32, luma, weights, even, odd);
  }
  sum = static_cast<std::uint64_t>(hn::GetLane(hn::SumOfLanes(d32, hn::Add(even, odd))));
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
