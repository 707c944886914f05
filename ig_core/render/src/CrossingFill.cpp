// The out-of-line parts of CrossingFill.h: the rarer colour work of a crossing and the fill on a
// stick.
#include "CrossingFill.h"

#include "RayMarch.h"

namespace fieldcast::core::plane_march {

using ray_march::floorToInt;
using ray_march::levelIndex;
using ray_march::pow2;
using ray_march::segmentLight;

void blendNextLevel(const CasterFrame& f, CasterThread& t, TileWindows& w, const ColumnPlane& c, Crossing& x,
                    double blend) noexcept {
  const int l = x.level;
  const double p = pow2(l);
  const double mMaj = (x.i + 0.5 + (x.onMinorLine ? x.phi : 0.0)) * p - 0.5;
  const double mMin = (x.j + 0.5 + (x.onMinorLine ? 0.0 : x.phi)) * p - 0.5;
  const double ux = levelIndex(c.xMajor ? mMaj : mMin, l + 1);
  const double uy = levelIndex(c.xMajor ? mMin : mMaj, l + 1);
  const int x0 = floorToInt(ux);
  const int y0 = floorToInt(uy);
  const auto fx = static_cast<float>(ux - x0);
  const auto fy = static_cast<float>(uy - y0);
  const int up = l + 1;
  std::uint32_t q00, q10, q01, q11;
  const int mask = f.tileMask;
  if ((x0 & mask) != mask && (y0 & mask) != mask && windowFor(f, t, w, up, x0, y0)) {
    // The 2×2 block lies in one tile: four loads.
    const auto lv = static_cast<std::size_t>(up);
    const std::uint32_t* p00 = w.tile[lv]->colourRgba + (((y0 - w.y0[lv]) << f.tileShift) + (x0 - w.x0[lv]));
    const std::ptrdiff_t row = std::ptrdiff_t{1} << f.tileShift;
    q00 = p00[0];
    q10 = p00[1];
    q01 = p00[row];
    q11 = p00[row + 1];
  } else {
    q00 = windowColour(f, t, w, up, x0, y0);
    q10 = windowColour(f, t, w, up, x0 + 1, y0);
    q01 = windowColour(f, t, w, up, x0, y0 + 1);
    q11 = windowColour(f, t, w, up, x0 + 1, y0 + 1);
  }
  const Rgb lo = mix(unpackRgb(q00), unpackRgb(q10), fx);
  const Rgb hi = mix(unpackRgb(q01), unpackRgb(q11), fx);
  x.colour = mix(x.colour, mix(lo, hi, fy), static_cast<float>(blend));
}

void relightCrossing(const CasterFrame& f, CasterThread& t, const ColumnPlane& c, Crossing& x) noexcept {
  const int vx = c.xMajor ? x.i : x.j;
  const int vy = c.xMajor ? x.j : x.i;
  const bool alongX = c.xMajor == x.onMinorLine;  // the segment's second voxel lies east, else north
  x.colour.v *= segmentLight(f, t, x.level, vx, vy, alongX, static_cast<float>(x.phi));
}

void fillOnStick(const CasterFrame& f, CasterThread& t, TileWindows& w, const ColumnPlane& c, const StickVoxel& near,
                 const StickVoxel& far, const Crossing& from, const Crossing& to, const CrossingSpan& span,
                 const ColumnFill& column, ColumnSink& sink, double vStop, int& qInOut, double& vqInOut) noexcept {
  const StickVoxel& s = far.id != 0 ? far : near;
  // A complex stick may be seen through (at level 0: its coarser texels are opaque); its pixels'
  // secondary rays need the column
  const Intrinsics& k = f.geo->intrinsics();
  const SeeThroughColumn through{&f, &t, k.cxPx + c.xc * k.fxPx, &w};
  const bool complex = f.seeThrough && f.sticks->entry(s.id).kind == StickKind::Complex;
  const StickSpan stick{f.sticks->texels(s.id, s.level), stickTexelCoordinate(s, from.heightQ, f.stickUnitsPerQ),
                        stickTexelCoordinate(s, to.heightQ, f.stickUnitsPerQ), f.shading.light().flat(),
                        complex ? &through : nullptr};
  if (sink.s != 1) {
    const PixelShader shading = column.shading;
    forEachSpanRow(
        span, column, shading, vStop, qInOut, vqInOut,
        [&](int q, const SpanPixel& p) { sink.emit(q, p.colour, p.rangeM); }, StickSpanPixel{stick});
  } else if (column.shading.grey) {
    fillStickSpan<true>(span, column, ColumnPixels{sink.pixels, sink.ranges, sink.bytesPerPixel}, vStop, qInOut,
                        vqInOut, stick);
  } else {
    fillStickSpan<false>(span, column, ColumnPixels{sink.pixels, sink.ranges, sink.bytesPerPixel}, vStop, qInOut,
                         vqInOut, stick);
  }
}

void minorLineColour(const CasterFrame& f, CasterThread& t, TileWindows& w, const ColumnPlane& c,
                     Crossing& x) noexcept {
  const int l = x.level;
  const int vx = c.xMajor ? x.i : x.j;
  const int vy = c.xMajor ? x.j : x.i;
  const std::uint32_t c0 = windowColour(f, t, w, l, vx, vy);
  const std::uint32_t c1 = c.xMajor ? windowColour(f, t, w, l, vx + 1, vy) : windowColour(f, t, w, l, vx, vy + 1);
  colourCrossing(f, t, w, c, x, c0, c1);
}

}  // namespace fieldcast::core::plane_march
