// A raster row's frame coordinates under a quadratic map or a homography in SIMD lanes (MapRow.h),
// one pixel per lane, compiled for every level Highway dispatches to: each lane evaluates the
// parabola or the ratio at its own pixel, as the scalar form does, so every level gives the same
// floats.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "MapRowLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "MapRow.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace fieldcast::warp::mapping::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void ParabolaRow(float a, float b, float c, int n, float* HWY_RESTRICT out) {
  const hn::ScalableTag<float> d;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const auto va = hn::Set(d, a), vb = hn::Set(d, b), vc = hn::Set(d, c);
  const auto step = hn::Set(d, static_cast<float>(lanes));
  auto u = hn::Add(hn::Iota(d, 0.0f), hn::Set(d, 0.5f));  // whole numbers and halves: exact
  int i = 0;
  for (; i + lanes <= n; i += lanes) {
    hn::StoreU(hn::Add(va, hn::Mul(u, hn::Add(vb, hn::Mul(u, vc)))), d, out + i);
    u = hn::Add(u, step);
  }
  parabolaRowScalar(a, b, c, i, n, out);
}

void RatioRow(const mapping::RatioRow& r, int n, float* HWY_RESTRICT xs, float* HWY_RESTRICT ys) {
  const hn::ScalableTag<float> d;
  const int lanes = static_cast<int>(hn::Lanes(d));
  const auto ax = hn::Set(d, r.ax), bx = hn::Set(d, r.bx), ay = hn::Set(d, r.ay), by = hn::Set(d, r.by);
  const auto aw = hn::Set(d, r.aw), bw = hn::Set(d, r.bw);
  const auto nan = hn::Set(d, std::numeric_limits<float>::quiet_NaN()), zero = hn::Zero(d);  // the scalar form's bits
  const auto step = hn::Set(d, static_cast<float>(lanes));
  auto u = hn::Add(hn::Iota(d, 0.0f), hn::Set(d, 0.5f));
  int i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto w = hn::Add(aw, hn::Mul(bw, u));
    const auto ahead = hn::Gt(w, zero);  // false for NaN
    hn::StoreU(hn::IfThenElse(ahead, hn::Div(hn::Add(ax, hn::Mul(bx, u)), w), nan), d, xs + i);
    hn::StoreU(hn::IfThenElse(ahead, hn::Div(hn::Add(ay, hn::Mul(by, u)), w), nan), d, ys + i);
    u = hn::Add(u, step);
  }
  ratioRowScalar(r, i, n, xs, ys);
}

}  // namespace fieldcast::warp::mapping::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fieldcast::warp::mapping {

HWY_EXPORT(ParabolaRow);

void parabolaRowLanes(float a, float b, float c, int n, float* out) noexcept {
  HWY_DYNAMIC_DISPATCH(ParabolaRow)(a, b, c, n, out);
}

HWY_EXPORT(RatioRow);

void ratioRowLanes(const RatioRow& r, int n, float* xs, float* ys) noexcept {
  HWY_DYNAMIC_DISPATCH(RatioRow)(r, n, xs, ys);
}

}  // namespace fieldcast::warp::mapping
#endif
