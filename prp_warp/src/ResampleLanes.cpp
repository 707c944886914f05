// The fixed-point bilinear sampling of a row in SIMD lanes, one pixel per 32-bit lane, compiled
// for every level Highway dispatches to (fieldcast/SimdLevel.h). Per lane: the frame coordinate
// to 1/256 px, clamped (NaN to 0) and checked against the margins; each row's two neighbours read
// by one gather (64-bit for RGB, 32-bit for grey); the x blend of an RGB channel one 16-bit
// multiply-add, the rest in 32-bit integers. The same bytes as SamplePixel.h's scalar reference.
// At level avx512vbmi a block is first offered to the staged sampling (SampleBlockVbmi.h),
// which reads the frame's rows whole instead of gathering; the gathers take the blocks it refuses.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "ResampleLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "SampleBlockVbmi.h"
#include "SamplePixel.h"

#include <fieldcast/SimdLevel.h>

#include <hwy/highway.h>

#include <type_traits>
#include <utility>

HWY_BEFORE_NAMESPACE();
namespace fieldcast::warp::sampling::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

/// Byte k (0 = lowest) of each 32-bit lane.
template <int K, class V>
HWY_INLINE V byteOf(V v) {
  return hn::And(hn::ShiftRight<8 * K>(v), hn::Set(hn::DFromV<V>(), 0xFF));
}

/// (left · (256 − f) + right · f) as left · 256 + (right − left) · f: one multiply.
template <class V>
HWY_INLINE V blend(V left, V right, V f) {
  return hn::Add(hn::ShiftLeft<kFracBits>(left), hn::Mul(hn::Sub(right, left), f));
}

template <int C>
std::uint32_t SampleRow(const Source& src, const float* HWY_RESTRICT xs, const float* HWY_RESTRICT ys, int n,
                        std::uint8_t* HWY_RESTRICT dst) {
  std::uint32_t violations = 0;
  int i = 0;
#if FIELDCAST_HWY_TARGET_IS_AVX512
  // At level avx512vbmi: the frame's bytes staged in registers instead of gathered where they fit
  // (SampleBlockVbmi.h). A run whose blocks all fit ends here, before the gathers' constants are
  // made (returning here took the NTSC kernel from 300 to 287 µs, with six runs a row then).
  const bool staged = simdVbmiEnabled() && stagedBlocksLikelyFit(C, xs, ys, n);
  // Whether the loop's next block is offered to the staged sampling first: not the one it just
  // refused, every one after a gathered block
  bool offerNext = staged;
  if (staged) {
    i = sampleBlocksVbmi(src, C, xs, ys, n, dst, violations);
    if (i + kStagedBlockPx > n) return violations + sampleRowScalar<C>(src, xs + i, ys + i, n - i, dst + C * i);
    offerNext = false;  // block i was refused: it is gathered below
  }
#endif
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const hn::Rebind<std::uint8_t, decltype(di)> d8;
  const int lanes = static_cast<int>(hn::Lanes(di));
  const auto zero = hn::Zero(df), half = hn::Set(df, 0.5f), unit = hn::Set(df, static_cast<float>(kOne));
  const auto widthPx = hn::Set(df, static_cast<float>(src.widthPx));
  const auto heightPx = hn::Set(df, static_cast<float>(src.heightPx));
  const auto maxX = hn::Set(df, static_cast<float>(src.widthPx - 1));
  const auto maxY = hn::Set(df, static_cast<float>(src.heightPx - 1));
  const auto lastX = hn::Set(di, src.widthPx - 2), lastY = hn::Set(di, src.heightPx - 2);
  // The gathers read x0 + 1 and y0 + 1 unchecked: the short cut below keeps x0 ≤ W − 2, y0 ≤ H − 2
  const auto shortCutMaxX = hn::Set(df, static_cast<float>(src.widthPx) - 1.5f);
  const auto shortCutMaxY = hn::Set(df, static_cast<float>(src.heightPx) - 1.5f);
  const auto fraction = hn::Set(di, kOne - 1);
  const auto stride = hn::Set(di, src.strideBytes);
  const auto round = hn::Set(di, 1 << (2 * kFracBits - 1));
  const auto* words = reinterpret_cast<const std::int32_t*>(src.base);  // gathered at byte offsets
#if HWY_TARGET != HWY_SCALAR
  const auto* pairs = reinterpret_cast<const std::int64_t*>(src.base);
  const hn::Repartition<std::int64_t, decltype(di)> d64;
  const hn::Half<decltype(di)> dHalf;
  const hn::Repartition<std::int16_t, decltype(di)> d16;
  // Eight bytes at each lane's offset, as the low and high 32 bits of each lane
  auto gatherPairs = [&](auto offsets) {
    const auto first = hn::BitCast(di, hn::GatherOffset(d64, pairs, hn::PromoteTo(d64, hn::LowerHalf(dHalf, offsets))));
    const auto second =
        hn::BitCast(di, hn::GatherOffset(d64, pairs, hn::PromoteTo(d64, hn::UpperHalf(dHalf, offsets))));
    return std::pair{hn::ConcatEven(di, second, first), hn::ConcatOdd(di, second, first)};
  };
#endif
  for (; i + lanes <= n; i += lanes) {
#if FIELDCAST_HWY_TARGET_IS_AVX512
    if (offerNext) {
      // The staged blocks from here on, up to one it refuses: that one is gathered below
      i += sampleBlocksVbmi(src, C, xs + i, ys + i, n - i, dst + C * i, violations);
      if (i + lanes > n) break;
    }
    offerNext = staged;
#endif
    const auto px = hn::LoadU(df, xs + i), py = hn::LoadU(df, ys + i);
    hn::Vec<decltype(di)> x0, y0, fx, fy;
    if (hn::AllTrue(df, hn::And(hn::And(hn::Ge(px, half), hn::Le(px, shortCutMaxX)),
                                hn::And(hn::Ge(py, half), hn::Le(py, shortCutMaxY))))) {
      // Every lane from the first pixel centre to a pixel before the last: no violation, no clamp
      // (the staged sampling's short cut, SampleBlockVbmi.cpp, goes on to the last centres: it
      // checks its loads)
      const auto ix = hn::ConvertTo(di, hn::Add(hn::Mul(hn::Sub(px, half), unit), half));
      const auto iy = hn::ConvertTo(di, hn::Add(hn::Mul(hn::Sub(py, half), unit), half));
      x0 = hn::ShiftRight<kFracBits>(ix);
      y0 = hn::ShiftRight<kFracBits>(iy);
      fx = hn::And(ix, fraction);
      fy = hn::And(iy, fraction);
    } else {
      const auto inside =
          hn::And(hn::And(hn::Ge(px, zero), hn::Le(px, widthPx)), hn::And(hn::Ge(py, zero), hn::Le(py, heightPx)));
      violations += static_cast<std::uint32_t>(lanes - static_cast<int>(hn::CountTrue(df, inside)));
      // Pixel-centre origin; a false compare (NaN) gives 0, as in the scalar form
      auto qx = hn::Sub(px, half), qy = hn::Sub(py, half);
      qx = hn::Min(hn::IfThenElseZero(hn::Ge(qx, zero), qx), maxX);
      qy = hn::Min(hn::IfThenElseZero(hn::Ge(qy, zero), qy), maxY);
      const auto ix = hn::ConvertTo(di, hn::Add(hn::Mul(qx, unit), half));
      const auto iy = hn::ConvertTo(di, hn::Add(hn::Mul(qy, unit), half));
      x0 = hn::Min(hn::ShiftRight<kFracBits>(ix), lastX);
      y0 = hn::Min(hn::ShiftRight<kFracBits>(iy), lastY);
      fx = hn::Sub(ix, hn::ShiftLeft<kFracBits>(x0));
      fy = hn::Sub(iy, hn::ShiftLeft<kFracBits>(y0));
    }
    const auto top = hn::Add(hn::Mul(y0, stride), C == 3 ? hn::Add(x0, hn::ShiftLeft<1>(x0)) : x0);
    const auto bottom = hn::Add(top, stride);
    if constexpr (C == 3) {
#if HWY_TARGET == HWY_SCALAR
      // One lane: the 64-bit reads below need two
      const auto two = hn::Set(di, 2);
      const auto upperLo = hn::GatherOffset(di, words, top), upperHi = hn::GatherOffset(di, words, hn::Add(top, two));
      const auto lowerLo = hn::GatherOffset(di, words, bottom);
      const auto lowerHi = hn::GatherOffset(di, words, hn::Add(bottom, two));
      // [L.r L.g L.b R.r] and [L.b R.r R.g R.b] of each row
      const auto uLr = byteOf<0>(upperLo), uLg = byteOf<1>(upperLo), uLb = byteOf<2>(upperLo);
      const auto uRr = byteOf<1>(upperHi), uRg = byteOf<2>(upperHi), uRb = byteOf<3>(upperHi);
      const auto lLr = byteOf<0>(lowerLo), lLg = byteOf<1>(lowerLo), lLb = byteOf<2>(lowerLo);
      const auto lRr = byteOf<1>(lowerHi), lRg = byteOf<2>(lowerHi), lRb = byteOf<3>(lowerHi);
      auto channel = [&](auto uL, auto uR, auto lL, auto lR) {
        const auto value = blend(blend(uL, uR, fx), blend(lL, lR, fx), fy);
        return hn::DemoteTo(d8, hn::ShiftRight<2 * kFracBits>(hn::Add(value, round)));
      };
      hn::StoreInterleaved3(channel(uLr, uRr, lLr, lRr), channel(uLg, uRg, lLg, lRg), channel(uLb, uRb, lLb, lRb), d8,
                            dst + 3 * i);
#else
      // Both neighbours of a row in one 64-bit read: [L.r L.g L.b R.r | R.g R.b · ·] on the upper
      // row; on the lower row two bytes back, [· · L.r L.g | L.b R.r R.g R.b], so that neither
      // read leaves the frame. Half as many gathered lanes as 32-bit reads of each pixel.
      const auto [upperLo, upperHi] = gatherPairs(top);
      const auto [lowerLo, lowerHi] = gatherPairs(hn::Sub(bottom, hn::Set(di, 2)));
      // Each channel's (left, right) as two 16-bit halves, blended along x by one 16-bit
      // multiply-add with the weights (256 − fx, fx): left · (256 − fx) + right · fx, exactly (on
      // x86 pmaddwd, whose pair sums stay in their lanes; elsewhere the rearrangement sums them)
      const auto low = hn::Set(di, 0xFF), high = hn::Set(di, 0xFF0000);
      const auto weightsX = hn::BitCast(d16, hn::Or(hn::Sub(hn::Set(di, kOne), fx), hn::ShiftLeft<16>(fx)));
      auto alongX = [&](auto pair) {
        auto odd = hn::Zero(di);
        const auto even = hn::ReorderWidenMulAccumulate(di, hn::BitCast(d16, pair), weightsX, hn::Zero(di), odd);
        return hn::RearrangeToOddPlusEven(even, odd);
      };
      const auto upperR = alongX(hn::Or(hn::And(upperLo, low), hn::And(hn::ShiftRight<8>(upperLo), high)));
      const auto upperG = alongX(hn::Or(byteOf<1>(upperLo), hn::ShiftLeft<16>(hn::And(upperHi, low))));
      const auto upperB = alongX(hn::Or(byteOf<2>(upperLo), hn::And(hn::ShiftLeft<8>(upperHi), high)));
      const auto lowerR = alongX(hn::Or(byteOf<2>(lowerLo), hn::And(hn::ShiftLeft<8>(lowerHi), high)));
      const auto lowerG = alongX(hn::Or(byteOf<3>(lowerLo), hn::And(lowerHi, high)));
      const auto lowerB = alongX(hn::Or(hn::And(lowerHi, low), hn::And(hn::ShiftRight<8>(lowerHi), high)));
      auto channel = [&](auto upper, auto lower) {
        return hn::DemoteTo(d8, hn::ShiftRight<2 * kFracBits>(hn::Add(blend(upper, lower, fy), round)));
      };
      hn::StoreInterleaved3(channel(upperR, lowerR), channel(upperG, lowerG), channel(upperB, lowerB), d8, dst + 3 * i);
#endif
    } else {
      // [L R · ·] on the upper row; on the lower row [· · L R] two bytes back, so that neither read
      // leaves the frame
      const auto upperPair = hn::GatherOffset(di, words, top);
      const auto lowerPair = hn::GatherOffset(di, words, hn::Sub(bottom, hn::Set(di, 2)));
      const auto upper = blend(byteOf<0>(upperPair), byteOf<1>(upperPair), fx);
      const auto lower = blend(byteOf<2>(lowerPair), byteOf<3>(lowerPair), fx);
      hn::StoreU(hn::DemoteTo(d8, hn::ShiftRight<2 * kFracBits>(hn::Add(blend(upper, lower, fy), round))), d8, dst + i);
    }
  }
  return violations + sampleRowScalar<C>(src, xs + i, ys + i, n - i, dst + C * i);
}

std::uint32_t SampleRowAnyChannels(const Source& src, int channels, const float* xs, const float* ys, int n,
                                   std::uint8_t* dst) {
  return channels == 3 ? SampleRow<3>(src, xs, ys, n, dst) : SampleRow<1>(src, xs, ys, n, dst);
}

}  // namespace fieldcast::warp::sampling::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fieldcast::warp::sampling {

HWY_EXPORT(SampleRowAnyChannels);

std::uint32_t sampleRowLanes(const Source& src, int channels, const float* xs, const float* ys, int n,
                             std::uint8_t* dst) noexcept {
  return HWY_DYNAMIC_DISPATCH(SampleRowAnyChannels)(src, channels, xs, ys, n, dst);
}

}  // namespace fieldcast::warp::sampling
#endif
