// The fixed-point bilinear sampling of a row in SIMD lanes, one pixel per 32-bit lane, compiled
// for every level Highway dispatches to (fieldcast/SimdLevel.h). Per lane: the frame coordinate
// to 1/256 px, clamped (NaN to 0) and checked against the margins; each neighbour pair read by a
// 32-bit gather; blends in 32-bit integers. The same bytes as SamplePixel.h's scalar reference.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "ResampleLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "SamplePixel.h"

#include <hwy/highway.h>

#include <type_traits>

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
  const auto stride = hn::Set(di, src.strideBytes);
  const auto round = hn::Set(di, 1 << (2 * kFracBits - 1));
  const auto* words = reinterpret_cast<const std::int32_t*>(src.base);  // gathered at byte offsets
  std::uint32_t violations = 0;
  int i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto px = hn::LoadU(df, xs + i), py = hn::LoadU(df, ys + i);
    const auto inside =
        hn::And(hn::And(hn::Ge(px, zero), hn::Le(px, widthPx)), hn::And(hn::Ge(py, zero), hn::Le(py, heightPx)));
    violations += static_cast<std::uint32_t>(lanes - static_cast<int>(hn::CountTrue(df, inside)));
    // Pixel-centre origin; a false compare (NaN) gives 0, as in the scalar form
    auto qx = hn::Sub(px, half), qy = hn::Sub(py, half);
    qx = hn::Min(hn::IfThenElseZero(hn::Ge(qx, zero), qx), maxX);
    qy = hn::Min(hn::IfThenElseZero(hn::Ge(qy, zero), qy), maxY);
    const auto ix = hn::ConvertTo(di, hn::Add(hn::Mul(qx, unit), half));
    const auto iy = hn::ConvertTo(di, hn::Add(hn::Mul(qy, unit), half));
    const auto x0 = hn::Min(hn::ShiftRight<kFracBits>(ix), lastX);
    const auto y0 = hn::Min(hn::ShiftRight<kFracBits>(iy), lastY);
    const auto fx = hn::Sub(ix, hn::ShiftLeft<kFracBits>(x0));
    const auto fy = hn::Sub(iy, hn::ShiftLeft<kFracBits>(y0));
    const auto top = hn::Add(hn::Mul(y0, stride), C == 3 ? hn::Add(x0, hn::ShiftLeft<1>(x0)) : x0);
    const auto bottom = hn::Add(top, stride);
    if constexpr (C == 3) {
      // [L.r L.g L.b R.r] at the left pixel and [L.b R.r R.g R.b] two bytes on: no byte read
      // beyond the right neighbour
      const auto two = hn::Set(di, 2);
      const auto topLeft = hn::GatherOffset(di, words, top);
      const auto topRight = hn::GatherOffset(di, words, hn::Add(top, two));
      const auto bottomLeft = hn::GatherOffset(di, words, bottom);
      const auto bottomRight = hn::GatherOffset(di, words, hn::Add(bottom, two));
      auto channel = [&](auto k) {
        constexpr int kByte = decltype(k)::value;  // std::integral_constant
        const auto upper = blend(byteOf<kByte>(topLeft), byteOf<kByte + 1>(topRight), fx);
        const auto lower = blend(byteOf<kByte>(bottomLeft), byteOf<kByte + 1>(bottomRight), fx);
        return hn::DemoteTo(d8, hn::ShiftRight<2 * kFracBits>(hn::Add(blend(upper, lower, fy), round)));
      };
      hn::StoreInterleaved3(channel(std::integral_constant<int, 0>()), channel(std::integral_constant<int, 1>()),
                            channel(std::integral_constant<int, 2>()), d8, dst + 3 * i);
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
