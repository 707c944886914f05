// Gain and R'G'B' → UYVY 4:2:2 of a row in SIMD lanes, one pixel per 32-bit lane, compiled for
// every level Highway dispatches to. Each lane computes its pixel's Y, Cb and Cr as the scalar
// form does; a pair's chroma sums its two lanes (even lanes keep Cb, odd lanes Cr), and each lane
// stores its two output bytes [C, Y]. The same bytes as PixelConversion.h's scalar reference. At
// level avx512vbmi the row's blocks of 16 take PixelConversionVbmi.h's path first.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "PixelConversionLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "PixelConversion.h"
#include "PixelConversionVbmi.h"

#include <fieldcast/SimdLevel.h>

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace fieldcast::warp::conversion::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void RgbToUyvyRow(const std::uint8_t* HWY_RESTRICT in, int widthPx, std::int32_t gainQ16,
                  std::uint8_t* HWY_RESTRICT out) {
  int x = 0;
#if FIELDCAST_HWY_TARGET_IS_AVX512
  // At level avx512vbmi: byte permutes and 16-bit multiply-adds (PixelConversionVbmi.h)
  if (simdVbmiEnabled()) x = rgbToUyvyBlocksVbmi(in, widthPx, gainQ16, out);
#endif
#if HWY_TARGET != HWY_SCALAR  // pairs need two lanes: one lane is the scalar form below
  const hn::ScalableTag<std::int32_t> di;
  const hn::Rebind<std::uint8_t, decltype(di)> d8;
  const hn::Rebind<std::uint16_t, decltype(di)> d16;
  const int lanes = static_cast<int>(hn::Lanes(di));
  const auto gain = hn::Set(di, gainQ16), half = hn::Set(di, 1 << 15), white = hn::Set(di, 255);
  const auto isCb = hn::Eq(hn::And(hn::Iota(di, 0), hn::Set(di, 1)), hn::Zero(di));  // even lanes
  auto gained = [&](auto bytes) {
    return hn::Min(hn::ShiftRight<16>(hn::Add(hn::Mul(hn::PromoteTo(di, bytes), gain), half)), white);
  };
  for (; x + lanes <= widthPx; x += lanes) {
    hn::Vec<decltype(d8)> r8, g8, b8;
    hn::LoadInterleaved3(d8, in + 3 * x, r8, g8, b8);
    const auto r = gained(r8), g = gained(g8), b = gained(b8);
    const auto y = hn::Add(hn::Add(hn::Set(di, 16 << 16), hn::Mul(r, hn::Set(di, 16829))),
                           hn::Add(hn::Mul(g, hn::Set(di, 33039)), hn::Mul(b, hn::Set(di, 6416))));
    const auto cb = hn::Add(hn::Sub(hn::Set(di, 128 << 16), hn::Mul(r, hn::Set(di, 9714))),
                            hn::Sub(hn::Mul(b, hn::Set(di, 28784)), hn::Mul(g, hn::Set(di, 19070))));
    const auto cr = hn::Add(hn::Sub(hn::Set(di, 128 << 16), hn::Mul(g, hn::Set(di, 24103))),
                            hn::Sub(hn::Mul(r, hn::Set(di, 28784)), hn::Mul(b, hn::Set(di, 4681))));
    // A pair's chroma: its two lanes summed (Shuffle2301 swaps the lanes of each pair)
    const auto chroma = hn::IfThenElse(isCb, hn::Add(cb, hn::Shuffle2301(cb)), hn::Add(cr, hn::Shuffle2301(cr)));
    const auto c = hn::ShiftRight<17>(hn::Add(chroma, hn::Set(di, 1 << 16)));
    const auto luma = hn::ShiftRight<16>(hn::Add(y, half));
    // Little-endian 16-bit [C, Y]: byte 2x is the chroma, 2x + 1 the luma
    hn::StoreU(hn::DemoteTo(d16, hn::Or(c, hn::ShiftLeft<8>(luma))), d16,
               reinterpret_cast<std::uint16_t*>(out + 2 * x));
  }
#endif
  toUyvyRowScalar(in + 3 * x, 3, widthPx - x, gainQ16, out + 2 * x);
}

}  // namespace fieldcast::warp::conversion::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fieldcast::warp::conversion {

HWY_EXPORT(RgbToUyvyRow);

void rgbToUyvyRowLanes(const std::uint8_t* in, int widthPx, std::int32_t gainQ16, std::uint8_t* out) noexcept {
  HWY_DYNAMIC_DISPATCH(RgbToUyvyRow)(in, widthPx, gainQ16, out);
}

}  // namespace fieldcast::warp::conversion
#endif
