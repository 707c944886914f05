// LaneLine.h's solve in SIMD lanes, one lane (column) per double lane, compiled for every level
// Highway dispatches to (fieldcast/SimdLevel.h): the reference's operations in the reference's
// order (floating-point contraction is off), so every level gives its bits.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "LaneLineLanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "LaneLine.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace fieldcast::core::plane_march::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void SolveLaneLine(LaneLine& l) {
  const hn::CappedTag<double, kLineLanes> d;  // (a wider vector would pass the arrays' end)
  const hn::Rebind<std::int32_t, decltype(d)> di;
  const hn::Rebind<std::uint8_t, decltype(di)> d8;
  const auto zero = hn::Zero(d), one = hn::Set(d, 1.0), ahead = hn::Set(d, 1e-6);
  const auto yLine = hn::Set(d, l.yLine), zLine = hn::Set(d, l.zLine);
  const auto yMinor = hn::Set(d, l.yMinor), zMinor = hn::Set(d, l.zMinor);
  const auto upZ = hn::Set(d, l.upZ), fwdZ = hn::Set(d, l.fwdZ);
  const auto rayZAtLine = hn::Set(d, l.rayZAtLine), dMaj = hn::Set(d, l.dMaj), ceiling = hn::Set(d, l.ceilingQ);
  // A mask as bytes 1 / 0
  const auto bytes = [&](auto mask) { return hn::DemoteTo(d8, hn::DemoteTo(di, hn::IfThenElseZero(mask, one))); };
  for (int n = 0; n < kLineLanes; n += static_cast<int>(hn::Lanes(d))) {
    const auto gA = hn::Load(d, l.gA + n), nZ = hn::Load(d, l.nZ + n), base = hn::Load(d, l.base + n);
    const auto h0 = hn::Load(d, l.h0 + n), h1 = hn::Load(d, l.h1 + n);
    const auto j = hn::PromoteTo(d, hn::LoadU(di, l.j + n));
    const auto g0 = hn::Add(hn::Add(hn::Mul(gA, j), hn::Mul(nZ, h0)), base);
    const auto dh = hn::Sub(h1, h0);
    const auto g1 = hn::Add(hn::Add(g0, gA), hn::Mul(nZ, dh));
    const auto dg = hn::Sub(g0, g1);
    const auto phi = hn::Div(g0, dg);
    const auto minor = hn::Add(j, phi);
    const auto h = hn::Add(h0, hn::Mul(phi, dh));
    const auto zc = hn::Add(hn::Add(zLine, hn::Mul(minor, zMinor)), hn::Mul(h, fwdZ));
    const auto yc = hn::Add(hn::Add(yLine, hn::Mul(minor, yMinor)), hn::Mul(h, upZ));
    hn::Store(yc, d, l.yc + n);
    hn::Store(zc, d, l.depth + n);
    hn::Store(phi, d, l.phi + n);
    hn::Store(h, d, l.heightQ + n);
    const auto solved = hn::And(hn::And(hn::Le(g0, zero), hn::Gt(g1, zero)), hn::Gt(zc, ahead));
    hn::StoreU(bytes(solved), d8, l.solved + n);
    hn::StoreU(bytes(hn::Gt(yc, hn::Mul(hn::Load(d, l.rowSlope + n), zc))), d8, l.fills + n);
    const auto rayZ = hn::Add(rayZAtLine, hn::Mul(dMaj, hn::Load(d, l.rayZPerDMaj + n)));
    const auto over = hn::And(hn::Gt(hn::Load(d, l.rayClimbs + n), zero), hn::Gt(rayZ, ceiling));
    hn::StoreU(bytes(over), d8, l.overTerrain + n);
    const auto drift = hn::Load(d, l.drift + n);
    hn::Store(hn::Add(minor, drift), d, l.jPos + n);
    // nextSegment (PlaneMarch.h)
    const auto up = hn::IfThenElseZero(hn::Le(g0, hn::Mul(hn::Sub(one, drift), dg)), one);
    const auto down = hn::IfThenElseZero(hn::Gt(g0, hn::Mul(hn::Neg(drift), dg)), one);
    hn::StoreU(hn::DemoteTo(di, hn::Sub(hn::Add(j, up), down)), di, l.jNext + n);
  }
}

}  // namespace fieldcast::core::plane_march::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fieldcast::core::plane_march {

HWY_EXPORT(SolveLaneLine);

void solveLaneLine(LaneLine& line) noexcept { HWY_DYNAMIC_DISPATCH(SolveLaneLine)(line); }

}  // namespace fieldcast::core::plane_march
#endif
