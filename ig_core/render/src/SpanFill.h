#pragma once
// The column-plane march's per-pixel work: filling the sub-rows between two crossings of a column
// with the terrain between them, interpolated perspective-correctly (1/depth is linear in the row),
// with its range and haze. fillSpanReference is the plain loop, one pixel at a time; fillSpan works
// out four pixels at once, one per lane of an SSE register, and is the same to the bit
// (SpanFillTest); fillStickSpan does the same on a stick's texels. Looking down, where the terrain
// is magnified and most spans are three or four sub-rows, this is two fifths of the frame's
// instructions; at low pitch most spans are one sub-row, and both hand those to the plain loop.

#include "Shading.h"
#include "StickShading.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace fieldcast::core {

/// Two crossings of a column that bound the sub-rows to fill: the near one's row v0 (sub-row
/// units), 1 / (v1 − v0), both crossings' 1 / depth (1/m) and colours.
struct CrossingSpan {
  float v0, invDv, invDepth0, invDepth1;
  Rgb c0, c1;
};

/// What the fill needs of a column besides its pixels, worked out once per march: the shading,
/// the sub-row pitch and the camera constants in float.
struct ColumnFill {
  PixelShader shading;
  float invS, cy, invFy, xc2;  ///< sub-row pitch, principal point row, 1/fy, 1 + xc²
  double invSd;                ///< the sub-row pitch in double (the march steps its row vq by it)
  int qTop = 0;                ///< the column's top sub-row (ColumnSink::qTop): fills stop there
};

/// One sub-row's terrain: colour with haze, and range (m).
struct SpanPixel {
  Rgb colour;
  float rangeM;
};

/// Where sub-row q meets the terrain between the span's crossings: the far crossing's weight
/// ts·(1/depth₁)·depth (perspective-correct) and the range. One reciprocal and one square root.
struct SpanPoint {
  float tw, rangeM;
};
inline SpanPoint spanPoint(const CrossingSpan& span, const ColumnFill& column, int q) noexcept {
  const float vqf = (static_cast<float>(q) + 0.5f) * column.invS;
  const float ts = std::clamp((vqf - span.v0) * span.invDv, 0.0f, 1.0f);
  const float depth = 1.0f / (span.invDepth0 + ts * (span.invDepth1 - span.invDepth0));
  const float tw = std::clamp(ts * span.invDepth1 * depth, 0.0f, 1.0f);
  const float yc = (column.cy - vqf) * column.invFy;
  return {tw, depth * std::sqrt(column.xc2 + yc * yc)};
}

/// The terrain sub-row q sees between the span's crossings: their colours mixed by the far one's
/// weight, with haze. Nothing carried over from the sub-row before.
inline SpanPixel spanPixel(const CrossingSpan& span, const ColumnFill& column, const PixelShader& shading,
                           int q) noexcept {
  const SpanPoint p = spanPoint(span, column, q);
  return {shading.terrain(mix(span.c0, span.c1, p.tw), p.rangeM), p.rangeM};
}

/// spanPixel as a function object: what forEachSpanRow colours terrain with.
struct TerrainSpanPixel {
  SpanPixel operator()(const CrossingSpan& span, const ColumnFill& column, const PixelShader& shading,
                       int q) const noexcept {
    return spanPixel(span, column, shading, q);
  }
};

struct CasterFrame;
struct CasterThread;
struct TileWindows;

/// A column's secondary rays (SeeThrough.h), for a span on a complex stick's see-through texels.
struct SeeThroughColumn {
  const CasterFrame* frame;
  CasterThread* thread;
  double uc;            ///< the column's centre, pixels
  TileWindows* window;  ///< the march's: a secondary ray reads the tiles its primary ray read
};
/// What sub-row q sees through the see-through texel its ray met at range `rangeM`: the colour
/// (hazed) and range of SeeThrough.h's secondary ray. Defined in SeeThrough.cpp.
SpanPixel seeThroughPixel(const SeeThroughColumn& column, int q, float rangeM) noexcept;

/// A span on a stick's side or top (StickShading.h): the stick's texels at its level, the near
/// and the far crossing's texel coordinates on it, and the light its texels are scaled by.
struct StickSpan {
  std::span<const std::uint32_t> texels;
  float s0 = 0.0f, s1 = 0.0f;
  float light = 1.0f;  ///< the frame's sun on colours without light of their own (TerrainLight::flat)
  const SeeThroughColumn* through = nullptr;  ///< a complex stick at level 0: its column's secondary rays
};

/// What sub-row q of a span on a stick sees: the texel at its place between the crossings (the far
/// crossing's weight as in spanPixel, nearest texel), with its range and haze; through a
/// see-through texel, what the secondary ray sees.
struct StickSpanPixel {
  StickSpan stick;
  SpanPixel operator()(const CrossingSpan& span, const ColumnFill& column, const PixelShader& shading,
                       int q) const noexcept {
    const SpanPoint p = spanPoint(span, column, q);
    const std::uint32_t texel = stickTexel(stick.texels, stick.s0 + (stick.s1 - stick.s0) * p.tw);
    if (stick.through != nullptr && seeThroughTexel(texel)) [[unlikely]]
      return seeThroughPixel(*stick.through, q, p.rangeM);
    return {shading.terrain(Rgb{unpackRgb(texel).v * stick.light}, p.rangeM), p.rangeM};
  }
};

/// A column with one sub-row per pixel: its pixel and its range in row 0 (rows are consecutive);
/// either may be null. Bytes per pixel: 1 for grey, 3 for colour.
struct ColumnPixels {
  std::uint8_t* pixels;
  float* ranges;
  std::size_t bytesPerPixel;
};

/// Calls put(q, pixel) with pixelOf (spanPixel by default) for sub-rows q, q−1, ... while their
/// centre vq lies below vStop (the far crossing's row), one at a time; advances q and vq as the
/// march steps them (vq by the sub-row pitch, and not past the column's top sub-row, qTop).
/// q ≥ qTop on entry. Everything
/// the loop reads is a local: pixel stores are bytes, which may alias anything, so values read
/// through a reference would be read again after every store.
template <typename Put, typename PixelOf = TerrainSpanPixel>
__attribute__((always_inline)) inline void forEachSpanRow(const CrossingSpan span, const ColumnFill& column,
                                                          const PixelShader& shading, double vStop, int& qInOut,
                                                          double& vqInOut, Put&& put,
                                                          const PixelOf pixelOf = {}) noexcept {
  const ColumnFill local = column;
  int q = qInOut;
  double vq = vqInOut;
  while (vq > vStop) {
    put(q, pixelOf(span, local, shading, q));
    if (--q < local.qTop) break;
    vq -= local.invSd;
  }
  qInOut = q;
  vqInOut = vq;
}

/// Fills the span's sub-rows of a column with one sub-row per pixel, one at a time (forEachSpanRow;
/// pixelOf: the terrain's colours, or a stick's texels). The reference for fillSpan.
template <bool kGrey, typename PixelOf = TerrainSpanPixel>
__attribute__((always_inline)) inline void fillSpanReference(const CrossingSpan span, const ColumnFill& column,
                                                             const ColumnPixels out, double vStop, int& qInOut,
                                                             double& vqInOut, const PixelOf pixelOf = {}) noexcept {
  PixelShader shading = column.shading;
  shading.grey = kGrey;  // a constant here, so the store has no per-pixel branch
  forEachSpanRow(
      span, column, shading, vStop, qInOut, vqInOut,
      [&](int q, const SpanPixel& p) {
        if (out.pixels != nullptr)
          shading.storePixel(out.pixels + static_cast<std::size_t>(q) * out.bytesPerPixel, p.colour, 1.0f);
        if (out.ranges != nullptr) out.ranges[q] = p.rangeM;
      },
      pixelOf);
}

#if defined(__SSE2__)
namespace span_lanes {

// std::clamp(x, 0, 1) lane by lane with the same results, NaN and −0 included: maxps and minps
// return their second operand on a tie or a NaN, as std::clamp's comparisons do.
inline __m128 clampUnit(__m128 x) noexcept { return _mm_min_ps(_mm_set1_ps(1.0f), _mm_max_ps(_mm_setzero_ps(), x)); }

// Lane k of a colour channel's register is sub-row q − k.
struct Channels {
  __m128 r, g, b;
};

// mix(a, b, t) of Shading.h, channel by channel: a + (b − a)·t, with b − a given.
inline Channels mixLanes(const Channels& a, const Channels& bMinusA, __m128 t) noexcept {
  return {_mm_add_ps(a.r, _mm_mul_ps(bMinusA.r, t)), _mm_add_ps(a.g, _mm_mul_ps(bMinusA.g, t)),
          _mm_add_ps(a.b, _mm_mul_ps(bMinusA.b, t))};
}

// PixelShader::storePixel's clamp to 0..255 and rounding (its scale is 1 here), as int32 lanes.
inline __m128i roundLanes(__m128 x) noexcept {
  const __m128 clamped = _mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()), _mm_set1_ps(255.0f));
  return _mm_cvttps_epi32(_mm_add_ps(clamped, _mm_set1_ps(0.5f)));
}

// The crossings' colours mixed by the far one's weight: spanPixel's colour, four sub-rows at once.
struct TerrainLanes {
  Channels c0, c1MinusC0;
  __attribute__((always_inline)) explicit TerrainLanes(const CrossingSpan& span) noexcept {
    const Float4 dc = span.c1.v - span.c0.v;
    c0 = {_mm_set1_ps(span.c0.v[0]), _mm_set1_ps(span.c0.v[1]), _mm_set1_ps(span.c0.v[2])};
    c1MinusC0 = {_mm_set1_ps(dc[0]), _mm_set1_ps(dc[1]), _mm_set1_ps(dc[2])};
  }
  /// The lanes' colours before haze for the far crossing's weights `tw`; no lane is see-through.
  __attribute__((always_inline)) Channels operator()(__m128 tw, unsigned& seeThrough) const noexcept {
    seeThrough = 0;
    return mixLanes(c0, c1MinusC0, tw);
  }
  SpanPixel throughPixel(int, float) const noexcept { return {}; }  // never asked
};

// A stick's texels: StickSpanPixel's colour, four sub-rows at once. The texel index is
// stickTexel's floor and clamps in lanes (maxps with the coordinate first turns a NaN into 0, as
// stickTexel does), the four texels read one by one.
struct StickLanes {
  const StickSpan& stick;
  /// The lanes' colours before haze; bit k of `seeThrough` set where lane k's texel is see-through
  /// and the stick has secondary rays (its colour is then throughPixel's).
  __attribute__((always_inline)) Channels operator()(__m128 tw, unsigned& seeThrough) const noexcept {
    const __m128 coordinate = _mm_add_ps(_mm_set1_ps(stick.s0), _mm_mul_ps(_mm_set1_ps(stick.s1 - stick.s0), tw));
    const __m128 last = _mm_set1_ps(static_cast<float>(stick.texels.size() - 1));
    alignas(16) std::int32_t index[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(index),
                    _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(coordinate, _mm_setzero_ps()), last)));
    alignas(16) std::uint32_t texel[4];
    seeThrough = 0;
    for (int k = 0; k < 4; ++k) {
      texel[k] = stick.texels[static_cast<std::size_t>(index[k])];
      seeThrough |= static_cast<unsigned>(seeThroughTexel(texel[k])) << k;
    }
    if (stick.through == nullptr) seeThrough = 0;
    const __m128i rgba = _mm_load_si128(reinterpret_cast<const __m128i*>(texel));
    const __m128i byte = _mm_set1_epi32(0xFF);
    const __m128 light = _mm_set1_ps(stick.light);
    return {_mm_mul_ps(_mm_cvtepi32_ps(_mm_and_si128(rgba, byte)), light),
            _mm_mul_ps(_mm_cvtepi32_ps(_mm_and_si128(_mm_srli_epi32(rgba, 8), byte)), light),
            _mm_mul_ps(_mm_cvtepi32_ps(_mm_and_si128(_mm_srli_epi32(rgba, 16), byte)), light)};
  }
  SpanPixel throughPixel(int q, float rangeM) const noexcept { return seeThroughPixel(*stick.through, q, rangeM); }
};

// fillSpanReference with four sub-rows at a time: lane k is sub-row q − k, and each colour
// channel has a register of its own; `colours` gives the lanes' colours (TerrainLanes or
// StickLanes), the rest is spanPixel's range and haze and the store. Same pixels and ranges, same
// q and vq afterwards, as the reference with the matching pixelOf.
template <bool kGrey, typename Colours>
__attribute__((always_inline)) inline void fillLanes(const CrossingSpan span, const ColumnFill& column,
                                                     const ColumnPixels out, double vStop, int& qInOut, double& vqInOut,
                                                     const Colours& colours) noexcept {
  PixelShader shading = column.shading;
  shading.grey = kGrey;
  const ColumnFill local = column;
  const double step = column.invSd;
  const __m128 v0 = _mm_set1_ps(span.v0), invDv = _mm_set1_ps(span.invDv);
  const __m128 invDepth0 = _mm_set1_ps(span.invDepth0), invDepth1 = _mm_set1_ps(span.invDepth1);
  const __m128 dInvDepth = _mm_set1_ps(span.invDepth1 - span.invDepth0);
  // spanPixel for sub-rows top, top−1, ..., top−rows+1 (rows ≤ 4), four lanes at once.
  const auto fourRows = [&](int top, int rows) __attribute__((always_inline)) {
    const __m128 vqf = _mm_mul_ps(
        _mm_add_ps(_mm_sub_ps(_mm_set1_ps(static_cast<float>(top)), _mm_set_ps(3, 2, 1, 0)), _mm_set1_ps(0.5f)),
        _mm_set1_ps(local.invS));
    const __m128 ts = clampUnit(_mm_mul_ps(_mm_sub_ps(vqf, v0), invDv));
    const __m128 depth = _mm_div_ps(_mm_set1_ps(1.0f), _mm_add_ps(invDepth0, _mm_mul_ps(ts, dInvDepth)));
    const __m128 tw = clampUnit(_mm_mul_ps(_mm_mul_ps(ts, invDepth1), depth));
    const __m128 yc = _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(local.cy), vqf), _mm_set1_ps(local.invFy));
    const __m128 rangeM = _mm_mul_ps(depth, _mm_sqrt_ps(_mm_add_ps(_mm_set1_ps(local.xc2), _mm_mul_ps(yc, yc))));
    unsigned seeThrough = 0;
    Channels colour = colours(tw, seeThrough);
    if (shading.hazeOn) {
      // The haze table's entries, capped as PixelShader::terrain caps them (minps(x, last) is
      // x < last ? x : last: a NaN range reads the last entry).
      alignas(16) std::int32_t index[4];
      const __m128 x = _mm_min_ps(_mm_mul_ps(rangeM, _mm_set1_ps(shading.invStepM)), _mm_set1_ps(shading.lastStep));
      _mm_store_si128(reinterpret_cast<__m128i*>(index), _mm_cvttps_epi32(x));
      const __m128 haze =
          _mm_set_ps(shading.haze[index[3]], shading.haze[index[2]], shading.haze[index[1]], shading.haze[index[0]]);
      const Channels horizon{_mm_set1_ps(shading.horizon.v[0]), _mm_set1_ps(shading.horizon.v[1]),
                             _mm_set1_ps(shading.horizon.v[2])};
      colour = mixLanes(
          colour, {_mm_sub_ps(horizon.r, colour.r), _mm_sub_ps(horizon.g, colour.g), _mm_sub_ps(horizon.b, colour.b)},
          haze);
    }
    if (out.pixels != nullptr) {
      alignas(16) std::uint32_t packed[4];
      if (kGrey) {
        // BT.601 luma, summed in storePixel's order.
        const __m128 luma =
            _mm_add_ps(_mm_add_ps(_mm_mul_ps(colour.r, _mm_set1_ps(0.299f)), _mm_mul_ps(colour.g, _mm_set1_ps(0.587f))),
                       _mm_mul_ps(colour.b, _mm_set1_ps(0.114f)));
        _mm_store_si128(reinterpret_cast<__m128i*>(packed), roundLanes(luma));
        for (int k = 0; k < rows; ++k) out.pixels[top - k] = static_cast<std::uint8_t>(packed[k]);
      } else {
        // R in the low byte, then G and B: each pixel's three bytes are the low three of its lane.
        const __m128i rgb = _mm_or_si128(roundLanes(colour.r), _mm_or_si128(_mm_slli_epi32(roundLanes(colour.g), 8),
                                                                            _mm_slli_epi32(roundLanes(colour.b), 16)));
        _mm_store_si128(reinterpret_cast<__m128i*>(packed), rgb);
        for (int k = 0; k < rows; ++k) std::memcpy(out.pixels + static_cast<std::size_t>(top - k) * 3, &packed[k], 3);
      }
    }
    alignas(16) float range[4];
    _mm_store_ps(range, rangeM);
    if (out.ranges != nullptr) {
      for (int k = 0; k < rows; ++k) out.ranges[top - k] = range[k];
    }
    if (seeThrough != 0) [[unlikely]] {
      // What the secondary rays of the see-through lanes see, over what the lanes wrote.
      for (int k = 0; k < rows; ++k) {
        if ((seeThrough >> k & 1u) == 0) continue;
        const SpanPixel p = colours.throughPixel(top - k, range[k]);
        if (out.pixels != nullptr)
          shading.storePixel(out.pixels + static_cast<std::size_t>(top - k) * out.bytesPerPixel, p.colour, 1.0f);
        if (out.ranges != nullptr) out.ranges[top - k] = p.rangeM;
      }
    }
  };
  int q = qInOut;
  double vq = vqInOut;
  while (vq > vStop) {
    // How many of the four sub-rows the span covers: vq steps down in double exactly as the
    // reference's does, so both stop on the same sub-row.
    double vqLast = vq;
    int n = 1;
    while (n < 4 && q - n >= local.qTop) {
      const double next = vqLast - step;
      if (!(next > vStop)) break;
      vqLast = next;
      ++n;
    }
    fourRows(q, n);
    q -= n;
    if (q < local.qTop) {
      vq = vqLast;  // the reference stops before stepping past the column's top sub-row
      break;
    }
    vq = vqLast - step;
  }
  qInOut = q;
  vqInOut = vq;
}

}  // namespace span_lanes
#endif

/// fillSpanReference four sub-rows at a time (span_lanes::fillLanes): same pixels and ranges, same
/// q and vq afterwards; q ≥ column.qTop on entry, and out.bytesPerPixel is kGrey ? 1 : 3. RT-safe.
template <bool kGrey>
__attribute__((always_inline)) inline void fillSpan(const CrossingSpan span, const ColumnFill& column,
                                                    const ColumnPixels out, double vStop, int& qInOut,
                                                    double& vqInOut) noexcept {
#if defined(__SSE2__)
  assert(qInOut >= column.qTop && out.bytesPerPixel == (kGrey ? 1u : 3u));
  if (vqInOut - vStop > 2.0 * column.invSd) {
    span_lanes::fillLanes<kGrey>(span, column, out, vStop, qInOut, vqInOut, span_lanes::TerrainLanes{span});
    return;
  }
  // A span of one or two sub-rows (most of them where the terrain is minified): the lanes'
  // set-up would cost more than they save.
#endif
  fillSpanReference<kGrey>(span, column, out, vStop, qInOut, vqInOut);
}

/// fillSpan on a stick's side or top: fillSpanReference with StickSpanPixel, four sub-rows at a
/// time; same pixels, ranges, q and vq, and the same secondary rays. RT-safe but for those.
template <bool kGrey>
__attribute__((always_inline)) inline void fillStickSpan(const CrossingSpan span, const ColumnFill& column,
                                                         const ColumnPixels out, double vStop, int& qInOut,
                                                         double& vqInOut, const StickSpan& stick) noexcept {
#if defined(__SSE2__)
  assert(qInOut >= column.qTop && out.bytesPerPixel == (kGrey ? 1u : 3u));
  if (vqInOut - vStop > 2.0 * column.invSd) {
    span_lanes::fillLanes<kGrey>(span, column, out, vStop, qInOut, vqInOut, span_lanes::StickLanes{stick});
    return;
  }
#endif
  fillSpanReference<kGrey>(span, column, out, vStop, qInOut, vqInOut, StickSpanPixel{stick});
}

}  // namespace fieldcast::core
